#pragma once
// The faces one hierarchy holds: a list of the mesh's face indices (a scene split into its
// deformable and rigid objects, docs/design.md "Deformable and rigid objects"), or, with no
// list, every face. A tree built over a subset stores the mesh's own face indices in its
// leaves (leaf_prim), so refit, restructure and every pair it reports need no mapping.
#include <cstdint>

#include "cdbench/core/hd.h"

namespace cdb {

struct FaceSubset {
  const uint32_t* faces;  // mesh face indices, or null: faces 0..count-1
  uint32_t count;

  CDB_HD_INLINE uint32_t face(uint32_t k) const { return faces ? faces[k] : k; }
};

}  // namespace cdb
