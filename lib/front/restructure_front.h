#pragma once
// (5) Restructure fronts (paper §4.3). After candidate subtrees were restructured
// (bvh/restructure.h), a front node (i, j) whose j lay strictly inside a candidate — a leaf
// of its range or an internal node below its root — names a node that no longer exists as
// it was. Valid nodes are kept and go through Algorithm 1 (update) as usual; invalid ones
// are replaced, per leaf i, by what covers the same leaves in the new subtree (valid nodes
// are "marked, compacted, and later handled by Algorithm 1 as usual"):
//  - i outside the candidate: i's invalid nodes partition the candidate's leaves [s, t];
//    the one starting at s becomes (i, root), the rest are dropped;
//  - i inside the candidate (the paper's self-collision special case: i's own position was
//    re-sorted): i's invalid nodes partition (i, t]; the one starting at i + 1 is replaced
//    by a traversal of the new subtree from leaf i's escape to the subtree's escape, the rest
//    are dropped. Nodes of i's front beyond t are still valid: they partition (t, N-1], and
//    a front is valid for whichever primitive sits at position i.
// So every leaf's front still partitions (i, N-1], and traversals from it stay exact.
// Classification reads the old tree's node ranges and so runs before the BVH restructure;
// it rewrites the front's node in place, so that a re-run of the front pass after a buffer
// grew sees the same classification.
#include <cstdint>

#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/restructure.h"
#include "cdbench/bvh/traverse.h"
#include "cdbench/front/operations.h"

namespace cdb {

// Node values the classification leaves in the front for the update that follows (besides
// kFrontDropped, front/front.h).
inline constexpr uint32_t kFrontRegenerate = kNoNode - 1;

struct ClassifyFrontFn {
  const uint32_t* node_first;  // of the tree before restructuring
  const uint32_t* node_last;
  CandidateView cand;
  const uint32_t* prim;
  uint32_t* node;
  CDB_HD void operator()(uint32_t e) const {
    const uint32_t j = node[e];
    if (j == kFrontDropped) return;
    const uint32_t k = ref_index(j);
    const uint32_t j_first = is_leaf(j) ? k : node_first[k];
    const uint32_t tag = cand.slot_of_leaf(j_first);
    if (tag == 0) return;
    const uint32_t c = tag - 1;
    // An internal node starting inside candidate c is strictly inside unless it is c's
    // root or one of its ancestors (which start at s too and end beyond t).
    if (!is_leaf(j) && (k == cand.node[c] || node_last[k] > cand.last[c])) return;
    const uint32_t i = prim[e];
    if (cand.slot_of_leaf(i) == tag)
      node[e] = j_first == i + 1 ? kFrontRegenerate : kFrontDropped;
    else
      node[e] = j_first == cand.first[c] ? cand.node[c] : kFrontDropped;
  }
};

// The front pass of operation 5 over a classified front: dropped nodes vanish, regenerate
// nodes traverse the restructured subtree of leaf i recording its stop nodes, and every
// other node is kept as it is and traversed as preserve does, for the frame's pairs. The
// kept nodes are left to the next update (Algorithm 1) to sprout or prune: this pass costs
// about a preserve plus the front's write, not an update. On the GPU the traversals are
// shared out within each warp (front/warp_traversal.h) when share_in_warp; a kept node's
// traversal records nothing, which its task carries in its query's top bit (kKeptQuery,
// front/operations.h).
struct RestructureFrontFn {
  using Stage = PairFrontStage;  // unstaged: the pass runs rarely, its sinks append directly
  static constexpr bool kWarpTraversal = true;
  FrontView view;  // a self front: restructuring renumbers the leaves cross fronts query from
  PairSink pairs;
  FrontSink front;
  CandidateView cand;
  const uint32_t* prim;
  const uint32_t* node;
  bool share_in_warp = false;
  // Front node e's own part: its push if kept, and the traversal left (kept nodes' query
  // tagged kKeptQuery).
  CDB_HD TraversalTask first_step(uint32_t e, Stage*) const {
    const uint32_t i = prim[e], j = node[e];
    if (j == kFrontDropped) return {};
    if (j == kFrontRegenerate) {
      const NodeBox b = view.query[i];
      const uint32_t c = cand.slot_of_leaf(i) - 1;
      // From leaf i's escape, which rides in its box (node_ref.h), to the subtree's.
      const uint32_t from = lane_link(b.lo.w), to = cand.escape[c];
      return {b.lo, b.hi, i, from, to, from != to};
    }
    front.push(i, j, 0);
    return front_node_step(view, pairs, i, j, kKeptQuery);
  }
  CDB_HD void operator()(uint32_t e, Stage* stage = nullptr) const {
    const TraversalTask t = first_step(e, stage);
    if (!t.busy) return;
    if (t.query & kKeptQuery)
      traverse_range<false>(view, t.query & ~kKeptQuery, t.lo, t.hi, t.node, t.end, pairs, FrontSink{});
    else
      traverse_range<true>(view, t.query, t.lo, t.hi, t.node, t.end, pairs, front);
  }
#if defined(__CUDACC__)
  __device__ void rest_in_warp(const TraversalTask& t, Stage*) const {
    traverse_in_warp(view.tree.bvh, t, pairs, [&](uint32_t q, uint32_t stop) {
      if (!(q & kKeptQuery)) front.push(q, stop, 1);
    });
  }
#endif
};

}  // namespace cdb
