#pragma once
// How the hierarchy-based pipelines divide a scene with declared queries (issue 4;
// docs/design.md "Deformable and rigid objects"): the faces of one set of objects go to one
// tree (T_D), the others' to a second (T_R), and each of three traversals runs only when a
// declared query can produce a pair in it:
//   self of T_D   pairs of two T_D faces (self of a T_D object, inter of two),
//   T_D against T_R  pairs of a T_D and a T_R face,
//   self of T_R   pairs of two T_R faces (self of a T_R object, inter of two).
// T_R takes the rigid objects and, under SplitRule::queries, each deformable object no self
// query names whose every inter partner is a deformable object in T_D (an avatar the cloth
// lies on: its pairs are all cloth-avatar pairs, which the cross traversal finds without
// the avatar's own self front). A scene without declared queries or where T_R would take
// nothing is not split: one tree over every face, its self traversal only (the pair filter
// keeps what the queries ask for).
#include <cstdint>
#include <string>
#include <vector>

#include "cdbench/geometry/mesh.h"

namespace cdb {

// Which objects T_R takes (--split-objects).
enum class SplitRule {
  rigid,    // the rigid objects
  queries,  // the rigid ones, and the deformable ones that only an inter with T_D names
};

const char* split_rule_name(SplitRule rule);
// Throws cdb::Error naming the known values.
SplitRule parse_split_rule(const std::string& name);

struct ObjectSplit {
  bool split = false;
  // Mesh face indices, ascending; empty unless split.
  std::vector<uint32_t> deformable_faces, rigid_faces;
  bool deformable_self = true;  // unsplit: the one tree's self traversal
  bool cross = false;
  bool rigid_self = false;
  // T_R holds deformable faces: a rebuild of T_D rebuilds it too (it is refitted
  // otherwise), so that it does not only loosen as the objects deform.
  bool rigid_tree_deforms = false;

  // T_D also serves the T_D-T_R traversal: its refitted leaves are the query boxes.
  bool deformable_tree() const { return deformable_self || cross; }
  bool rigid_tree() const { return cross || rigid_self; }
  // Whether T_R builds on a frame that builds T_D (`rebuild`): on the first frame, and with
  // every rebuild where it deforms; refitted otherwise.
  bool rigid_tree_builds(bool first_frame, bool rebuild) const {
    return first_frame || (rebuild && rigid_tree_deforms);
  }
};

ObjectSplit split_objects(const Topology& topology, SplitRule rule);

}  // namespace cdb
