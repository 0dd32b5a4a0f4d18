#pragma once
#include <cstdint>

#include "cdbench/bvh/node_box.h"
#include "cdbench/core/float_bits.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

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

// A box carries its links in the spare lane of each corner, bit for bit: an internal
// node's node_box[k].lo.w holds node_left[k] and .hi.w node_escape[k]; a leaf's
// leaf_box[i].lo.w holds leaf_escape[i] and .hi.w leaf_prim[i]. bvh/traverse.h reads
// them with the box. Moved as raw bits, never as arithmetic floats.
CDB_HD_INLINE float link_lane(uint32_t ref) { return bits_float(ref); }
CDB_HD_INLINE uint32_t lane_link(float lane) { return float_bits(lane); }

// Writes leaf i's lanes (the layout of bvh/order.h; the refit writes whole corners).
CDB_HD_INLINE void set_leaf_lanes(NodeBox& box, uint32_t escape, uint32_t prim) {
  box.lo.w = link_lane(escape);
  box.hi.w = link_lane(prim);
}

}  // namespace cdb
