#pragma once
// (5) Restructure fronts (paper §4.3). After candidate subtrees were restructured
// (bvh/restructure.h), a front node (i, j) whose j lay strictly inside a candidate — a leaf
// of its range or an internal node below its root — names a node that no longer exists as
// it was. Valid nodes are kept and go through Algorithm 1 (update) as usual; invalid ones
// are replaced, per leaf i, by what covers the same leaves in the new subtree:
//  - i outside the candidate: i's invalid nodes partition the candidate's leaves [s, t];
//    the one starting at s becomes (i, root), the rest are dropped;
//  - i inside the candidate (the paper's self-collision special case: i's own position was
//    re-sorted): i's invalid nodes partition (i, t]; the one starting at i + 1 is replaced
//    by a traversal of the new subtree from leaf i's escape to the subtree's escape, the rest
//    are dropped. Nodes of i's front beyond t are still valid: they partition (t, N-1], and
//    a front is valid for whichever primitive sits at position i.
// So every leaf's front still partitions (i, N-1] and the update stays exact.
// Classification reads the old tree's node ranges and so runs before the BVH restructure;
// it rewrites the front's node in place.
#include <cstdint>

#include "bvh/node_ref.h"
#include "bvh/restructure.h"
#include "front/operations.h"

namespace cdb {

// Node values the classification leaves in the front for the update that follows.
inline constexpr uint32_t kFrontDropped = kNoNode;
inline constexpr uint32_t kFrontRegenerate = kNoNode - 1;

struct ClassifyFrontFn {
  const uint32_t* node_first;  // of the tree before restructuring
  const uint32_t* node_last;
  CandidateView cand;
  const uint32_t* prim;
  uint32_t* node;
  CDB_HD void operator()(uint32_t e) const {
    const uint32_t j = node[e];
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

// Algorithm 1 over a classified front: dropped nodes vanish, regenerate nodes traverse the
// restructured subtree of leaf i, the rest update as usual.
struct RestructuredUpdateFn {
  FrontTree tree;
  PairSink pairs;
  FrontSink front;
  CandidateView cand;
  const uint32_t* prim;
  const uint32_t* node;
  CDB_HD void operator()(uint32_t e) const {
    const uint32_t i = prim[e], j = node[e];
    if (j == kFrontDropped) return;
    if (j == kFrontRegenerate) {
      const uint32_t c = cand.slot_of_leaf(i) - 1;
      const vec4f lo = tree.bvh.leaf_lo[i], hi = tree.bvh.leaf_hi[i];
      traverse_range<true>(tree, i, lo, hi, tree.bvh.leaf_escape[i], cand.escape[c], pairs, front);
      return;
    }
    update_front_node(tree, pairs, front, i, j);
  }
};

}  // namespace cdb
