#pragma once
#include <cstdint>

#include "core/hd.h"

namespace cdb {

// A reference to a BVH node: internal node index, or leaf index with the top bit set
// (the paper's "external" flag, Fig. 2.2). kNoNode (-1) marks "past the end".
inline constexpr uint32_t kLeafBit = 0x80000000u;
inline constexpr uint32_t kNoNode = 0xFFFFFFFFu;
// Largest leaf count a reference can address (leaf bit plus kNoNode reserved).
inline constexpr uint32_t kMaxLeaves = 0x7FFFFFFFu;

CDB_HD_INLINE bool is_leaf(uint32_t ref) { return (ref & kLeafBit) != 0; }
CDB_HD_INLINE uint32_t leaf_ref(uint32_t leaf) { return leaf | kLeafBit; }
CDB_HD_INLINE uint32_t ref_index(uint32_t ref) { return ref & ~kLeafBit; }

}  // namespace cdb
