#pragma once
// The stackless depth-first traversal by escape indices (paper Alg. 1, lines 1-11) against a
// query box, in the shape of cuBQL's forEachLeaf, for the self and cross queries, the front
// operations and the warp-shared preserve (front/warp_traversal.h). A step loads the node's
// links (and a leaf's primitive) together with its box, before the overlap test picks one:
// the loads are in flight at once, so a step costs one memory round trip, where loading the
// chosen link after the test cost two, and a hit's pair needs no further load. The links
// and a leaf's primitive come in the box's spare lanes (node_ref.h).
#include <cstdint>

#include "cdbench/bvh/bvh_view.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/aabb.h"

namespace cdb {

struct NextNode {
  uint32_t next;    // the left child of an internal node that overlaps, else the escape index
  uint32_t escape;  // the escape index: where the node's subtree ends
  uint32_t prim;    // a leaf's primitive
  bool leaf_hit;    // a leaf that overlaps: a pair
  bool stop;        // a leaf, or an internal node that misses: where a front records a node
};

// Each kind loads its box in a branch of its own, from its own array. Loaded through one
// address chosen by kind (one body for both, through next_node_in), nvcc split each box into
// eight 4-byte loads: the PTX of the staged preserve kernel at 474c354 held 8 of its 36
// 16-byte loads, and 42 loads of one float, and the steady frames ran 0.60-0.91x of
// 1c78245's on the H100 (results/2026-12-07-h100/bar). tests/cli/ptx_tests.sh keeps it so.
CDB_HD_INLINE NextNode next_node(const BvhView& bvh, uint32_t node, const vec4f& lo, const vec4f& hi) {
  const uint32_t k = ref_index(node);
  if (is_leaf(node)) {
    const NodeBox b = bvh.leaf_box[k];
    const uint32_t escape = lane_link(b.lo.w);
    return {escape, escape, lane_link(b.hi.w), overlaps(lo, hi, b.lo, b.hi), true};
  }
  // The links ride in the box's spare lanes (node_ref.h): two loads from one 32-byte sector
  // (bvh/node_box.h) where four arrays took four lines.
  const NodeBox b = bvh.node_box[k];
  const bool hit = overlaps(lo, hi, b.lo, b.hi);
  const uint32_t escape = lane_link(b.hi.w);
  return {hit ? lane_link(b.lo.w) : escape, escape, 0u, false, !hit};
}

// next_node's step with the node's box loaded already (PreserveTwoNodesFn).
CDB_HD_INLINE NextNode next_node_in(const NodeBox& b, uint32_t node, const vec4f& lo, const vec4f& hi) {
  const bool hit = overlaps(lo, hi, b.lo, b.hi);
  if (is_leaf(node)) {
    const uint32_t escape = lane_link(b.lo.w);
    return {escape, escape, lane_link(b.hi.w), hit, true};
  }
  const uint32_t escape = lane_link(b.hi.w);
  return {hit ? lane_link(b.lo.w) : escape, escape, 0u, false, !hit};
}

// What a step meets goes to callbacks, taken by value and inlined (no indirection in the
// loop): on_leaf_hit(prim) for a leaf that overlaps, on_stop(node) for a stop node. They
// capture scalars, not the query box: a captured box made nvcc branch in the overlap test.
struct NoStop {
  CDB_HD_INLINE void operator()(uint32_t) const {}
};

template <class OnLeafHit, class OnStop = NoStop>
CDB_HD_INLINE NextNode visit(const BvhView& bvh, uint32_t node, const vec4f& lo, const vec4f& hi,
                             OnLeafHit on_leaf_hit, OnStop on_stop = {}) {
  const NextNode step = next_node(bvh, node, lo, hi);
  if (step.leaf_hit) on_leaf_hit(step.prim);
  if (step.stop) on_stop(node);
  return step;
}

// From `node` up to (not including) `end` in depth-first order; kNoNode: to the end.
template <class OnLeafHit, class OnStop = NoStop>
CDB_HD_INLINE void traverse(const BvhView& bvh, const vec4f& lo, const vec4f& hi, uint32_t node,
                            uint32_t end, OnLeafHit on_leaf_hit, OnStop on_stop = {}) {
  while (node != end) node = visit(bvh, node, lo, hi, on_leaf_hit, on_stop).next;
}

}  // namespace cdb
