#include "cdbench/geometry/object_split.h"

#include "cdbench/core/error.h"

namespace cdb {

const char* split_rule_name(SplitRule rule) { return rule == SplitRule::rigid ? "rigid" : "queries"; }

SplitRule parse_split_rule(const std::string& name) {
  if (name == "rigid") return SplitRule::rigid;
  if (name == "queries") return SplitRule::queries;
  fail("unknown object split '" + name + "' (rigid, queries)");
}

ObjectSplit split_objects(const Topology& topology, SplitRule rule) {
  ObjectSplit s;
  if (!topology.queries.declared) return s;
  const auto& objects = topology.objects;
  // Object indices are validated with the pair filter tables (geometry/objects.h).
  auto valid = [&](uint32_t o) { return o < objects.size(); };
  std::vector<bool> self_named(objects.size(), false);
  for (uint32_t o : topology.queries.self)
    if (valid(o)) self_named[o] = true;
  // Which tree each object goes to: T_R takes the rigid ones and, under `queries`, each
  // deformable one no self query names that only inters with deformable, self-named objects
  // (which stay in T_D) name.
  std::vector<bool> in_rigid(objects.size(), false);
  for (uint32_t o = 0; o < objects.size(); ++o) {
    if (objects[o].rigid) {
      in_rigid[o] = true;
      continue;
    }
    if (rule != SplitRule::queries || self_named[o]) continue;
    bool named = false, partners_in_deformable = true;
    for (const auto& [a, b] : topology.queries.inter) {
      if (a != o && b != o) continue;
      const uint32_t partner = a == o ? b : a;
      named = true;
      partners_in_deformable = partners_in_deformable && valid(partner) && partner != o &&
                               !objects[partner].rigid && self_named[partner];
    }
    in_rigid[o] = named && partners_in_deformable;
  }
  bool any_rigid = false;
  for (uint32_t o = 0; o < objects.size(); ++o) any_rigid = any_rigid || in_rigid[o];
  if (!any_rigid) return s;
  s.split = true;
  s.deformable_self = false;
  for (uint32_t o = 0; o < objects.size(); ++o) {
    s.rigid_tree_deforms = s.rigid_tree_deforms || (in_rigid[o] && !objects[o].rigid);
    for (uint32_t f = objects[o].first_face; f < objects[o].first_face + objects[o].num_faces; ++f)
      (in_rigid[o] ? s.rigid_faces : s.deformable_faces).push_back(f);
  }
  auto rigid = [&](uint32_t o) { return valid(o) && in_rigid[o]; };
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
