#include "cdbench/geometry/objects.h"

#include "cdbench/core/error.h"

namespace cdb {

PairFilterTables pair_filter_tables(const std::vector<SceneObject>& objects, const ObjectQueries& q,
                                    size_t num_faces) {
  if (objects.size() > kMaxQueryObjects)
    fail("scene has " + std::to_string(objects.size()) + " objects; declared queries support at most " +
         std::to_string(kMaxQueryObjects));
  PairFilterTables t;
  t.face_object.assign(num_faces, uint32_t(-1));
  for (uint32_t o = 0; o < objects.size(); ++o) {
    const SceneObject& ob = objects[o];
    if (size_t(ob.first_face) + ob.num_faces > num_faces)
      fail("object '" + ob.name + "' covers faces past the scene's " + std::to_string(num_faces));
    for (uint32_t f = ob.first_face; f < ob.first_face + ob.num_faces; ++f) {
      if (t.face_object[f] != uint32_t(-1))
        fail("objects '" + objects[t.face_object[f]].name + "' and '" + ob.name + "' share face " +
             std::to_string(f));
      t.face_object[f] = o;
    }
  }
  for (size_t f = 0; f < num_faces; ++f)
    if (t.face_object[f] == uint32_t(-1)) fail("face " + std::to_string(f) + " belongs to no object");
  t.partners.assign(objects.size(), 0);
  auto check = [&](uint32_t o) {
    if (o >= objects.size()) fail("query names object " + std::to_string(o) + " of " + std::to_string(objects.size()));
  };
  for (uint32_t o : q.self) {
    check(o);
    t.partners[o] |= uint64_t(1) << o;
  }
  for (const auto& [a, b] : q.inter) {
    check(a);
    check(b);
    if (a == b) fail("inter query of object '" + objects[a].name + "' with itself: declare it under self");
    t.partners[a] |= uint64_t(1) << b;
    t.partners[b] |= uint64_t(1) << a;
  }
  return t;
}

}  // namespace cdb
