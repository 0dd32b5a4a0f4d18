#pragma once
#include <cstdint>

#include "cdbench/core/hd.h"

namespace cdb {

// One reported pair of triangles, a < b, in the input's own face numbering.
struct PrimPair {
  uint32_t a, b;
};

CDB_HD_INLINE PrimPair make_pair_ordered(uint32_t i, uint32_t j) {
  return i < j ? PrimPair{i, j} : PrimPair{j, i};
}

CDB_HD_INLINE uint64_t pair_key(PrimPair p) { return (uint64_t(p.a) << 32) | p.b; }

}  // namespace cdb
