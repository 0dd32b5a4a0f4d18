#pragma once
// What the refit's kernels share (bvh/refit.h, bvh/refit_levels.h): the counters a refit
// zeroes on its way, and the hand-over at a node spanning tiles.
#include <cstdint>

#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/tree_arrays.h"
#include "cdbench/core/atomics.h"
#include "cdbench/core/vec.h"

namespace cdb {

// Counters a refit zeroes on its way (the pair buffer's, before the front pass that counts
// into them): a steady frame then needs no launch of its own to reset them.
struct CounterReset {
  unsigned long long* counters = nullptr;
  uint32_t count = 0;
};

// The device-scope hand-over at spanning node p: false for the first of its two arrivals
// (parity of refit_flag, bvh/refit.h); the second gets the sibling's box.
CDB_HD_INLINE bool span_handover(uint32_t* flag, uint32_t p, uint32_t sibling, const TreeArrays& tree, vec4f& slo,
                                 vec4f& shi) {
  if ((atomic_add_acq_rel(&flag[p], 1u) & 1u) == 0) return false;
  const NodeBox* box = is_leaf(sibling) ? &tree.leaf_box[ref_index(sibling)] : &tree.node_box[sibling];
  slo = load_coherent(&box->lo);
  shi = load_coherent(&box->hi);
  return true;
}

}  // namespace cdb
