#pragma once
// How the hierarchy-based pipelines divide a scene with declared queries and rigid objects
// (issue 4; docs/design.md "Deformable and rigid objects"): the faces of deformable
// objects go to one tree (T_D), those of rigid objects to another (T_R), and each of three
// traversals runs only when a declared query can produce a pair in it:
//   self of T_D   pairs of two deformable faces (self of a deformable object, D-D inter),
//   D against T_R pairs of a deformable and a rigid face (D-R inter),
//   self of T_R   pairs of two rigid faces (self of a rigid object, R-R inter).
// A scene without declared queries or without rigid objects is not split: one tree over
// every face, its self traversal only (the pair filter keeps what the queries ask for).
#include <cstdint>
#include <vector>

#include "cdbench/geometry/mesh.h"

namespace cdb {

struct ObjectSplit {
  bool split = false;
  // Mesh face indices, ascending; empty unless split.
  std::vector<uint32_t> deformable_faces, rigid_faces;
  bool deformable_self = true;  // unsplit: the one tree's self traversal
  bool cross = false;
  bool rigid_self = false;

  // T_D also serves the D-R traversal: its refitted leaves are the query boxes.
  bool deformable_tree() const { return deformable_self || cross; }
  bool rigid_tree() const { return cross || rigid_self; }
};

ObjectSplit split_objects(const Topology& topology);

}  // namespace cdb
