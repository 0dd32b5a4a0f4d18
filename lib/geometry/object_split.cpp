#include "cdbench/geometry/object_split.h"

namespace cdb {

ObjectSplit split_objects(const Topology& topology) {
  ObjectSplit s;
  const auto& objects = topology.objects;
  bool any_rigid = false;
  for (const SceneObject& o : objects) any_rigid = any_rigid || o.rigid;
  if (!topology.queries.declared || !any_rigid) return s;
  s.split = true;
  s.deformable_self = false;
  for (const SceneObject& o : objects)
    for (uint32_t f = o.first_face; f < o.first_face + o.num_faces; ++f)
      (o.rigid ? s.rigid_faces : s.deformable_faces).push_back(f);
  // Object indices are validated with the pair filter tables (geometry/objects.h).
  auto rigid = [&](uint32_t o) { return o < objects.size() && objects[o].rigid; };
  for (uint32_t o : topology.queries.self) (rigid(o) ? s.rigid_self : s.deformable_self) = true;
  for (const auto& [a, b] : topology.queries.inter) {
    if (rigid(a) && rigid(b))
      s.rigid_self = true;
    else if (rigid(a) || rigid(b))
      s.cross = true;
    else
      s.deformable_self = true;
  }
  return s;
}

}  // namespace cdb
