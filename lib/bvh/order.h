#pragma once
// Depth-first layout of the internal nodes by histogram sort (paper §3.2, Fig. 2.3).
// In depth-first order the leftmost leaves of the visited internal nodes never decrease, so
// each leaf l is a segment holding the chain of internal nodes whose leftmost leaf is l
// (count_log[l] of them, its LCL value, counted by the build). An exclusive scan gives
// offset_log; each segment then numbers its chain top to bottom, and one scatter moves
// every node with its links to its place. No comparison sort.
#include <cstdint>

#include "cdbench/exec/balance.h"
#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/refit_index.h"

namespace cdb {

// Build-numbered tree -> depth-first layout, for the whole tree or for one subtree whose
// leaves are [s, t] (bvh/restructure.h). Only three things differ for a subtree: nodes whose
// range ends at leaf t escape to `last_escape` (what followed the subtree before), the
// subtree root keeps the parent it had (`root_parent`), and indices start at its root's.
struct DepthFirstLayout {
  BuildArrays build;
  TreeArrays tree;

  CDB_HD_INLINE uint32_t remap(uint32_t ref) const {
    return (ref == kNoNode || is_leaf(ref)) ? ref : build.new_index[ref];
  }
  // Walks segment l's chain bottom-up: the lowest node whose leftmost leaf is l is internal
  // node l (leaf l is its left child), and each next one is the parent. `base` is the
  // index of the segment's first node.
  CDB_HD_INLINE void number_chain(uint32_t l, uint32_t base) const {
    const uint32_t c = build.count_log[l];
    uint32_t node = l;
    const uint32_t bottom = base + c - 1;
    for (uint32_t s = 0; s < c; ++s) {
      build.new_index[node] = bottom - s;
      node = build.parent[node];
    }
  }
  CDB_HD_INLINE void place_node(uint32_t k, uint32_t t, uint32_t last_escape,
                                uint32_t root_parent) const {
    const uint32_t p = build.new_index[k];
    const uint32_t left = remap(build.left[k]);
    tree.node_left[p] = left;
    tree.node_right[p] = remap(build.right[k]);
    const uint32_t parent = build.parent[k];
    tree.node_parent[p] = parent == kNoNode ? root_parent : build.new_index[parent];
    const uint32_t r = build.last[k];
    tree.node_first[p] = build.first[k];
    tree.node_last[p] = r;
    // Escape (Fig. 2.2): the node after subtree [l, r] in depth-first order is the right
    // child of internal node r; past the last leaf it is whatever followed the whole range.
    const uint32_t escape = r == t ? last_escape : remap(build.right[r]);
    tree.node_escape[p] = escape;
    const vec4f lo = build.lo[k], hi = build.hi[k];
    tree.node_box[p] = {{lo.x, lo.y, lo.z, link_lane(left)}, {hi.x, hi.y, hi.z, link_lane(escape)}};
  }
  CDB_HD_INLINE void link_leaf(uint32_t i, uint32_t t, uint32_t last_escape) const {
    const uint32_t escape = i == t ? last_escape : remap(build.right[i]);
    tree.leaf_escape[i] = escape;
    tree.leaf_parent[i] = build.new_index[tree.leaf_parent[i]];
    set_leaf_lanes(tree.leaf_box[i], escape, tree.leaf_prim[i]);
  }
};

template <class Exec>
DepthFirstLayout depth_first_layout(Lbvh<Exec>& bvh) {
  return {bvh.build(), bvh.tree()};
}

struct NumberChainFn {
  DepthFirstLayout layout;
  CDB_HD void operator()(uint32_t l) const { layout.number_chain(l, layout.build.offset_log[l]); }
};

struct ScatterNodesFn {
  DepthFirstLayout layout;
  uint32_t n;
  CDB_HD void operator()(uint32_t k) const { layout.place_node(k, n - 1, kNoNode, kNoNode); }
};

struct LinkLeavesFn {
  DepthFirstLayout layout;
  uint32_t n;
  CDB_HD void operator()(uint32_t i) const { layout.link_leaf(i, n - 1, kNoNode); }
};

struct SingleLeafFn {
  TreeArrays tree;
  CDB_HD void operator()(uint32_t) const {
    tree.leaf_parent[0] = kNoNode;
    tree.leaf_escape[0] = kNoNode;
    set_leaf_lanes(tree.leaf_box[0], kNoNode, tree.leaf_prim[0]);
  }
};

// A one-leaf tree: no internal node, nothing after the leaf (both orders).
template <class Exec>
void order_single_leaf(Exec& exec, Lbvh<Exec>& bvh) {
  exec.for_each_n(1, SingleLeafFn{bvh.tree()});
  index_refit(exec, bvh);
}

template <class Exec>
void order_depth_first(Exec& exec, Lbvh<Exec>& bvh) {
  const uint32_t n = bvh.num_leaves;
  if (n == 0) return;
  if (n == 1) return order_single_leaf(exec, bvh);
  exec.exclusive_scan(bvh.count_log.data(), bvh.offset_log.data(), size_t(n) + 1,
                      bvh.temp.data(), bvh.temp.size());
  const DepthFirstLayout layout = depth_first_layout(bvh);
  exec.for_each_n(n, NumberChainFn{layout}, Balance::uneven);
  exec.for_each_n(n - 1, ScatterNodesFn{layout, n});
  exec.for_each_n(n, LinkLeavesFn{layout, n});
  index_refit(exec, bvh);
}

// The radix-sort baseline of the same layout (for the paper's Fig. 6 comparison, issue
// "radix-order"): depth-first preorder is the order of (leftmost leaf, then larger subtree
// first), so one key sort of the internal nodes gives every new index without the count
// log. Same result as order_depth_first, node for node (tested).
struct DepthFirstKeyFn {
  const uint32_t* build_first;
  const uint32_t* build_last;
  uint64_t* keys;
  uint32_t* iota;
  CDB_HD void operator()(uint32_t k) const {
    keys[k] = (uint64_t(build_first[k]) << 32) | (0xFFFFFFFFu - (build_last[k] - build_first[k]));
    iota[k] = k;
  }
};

struct IndexFromSortedFn {
  const uint32_t* sorted_node;
  uint32_t* new_index;
  CDB_HD void operator()(uint32_t p) const { new_index[sorted_node[p]] = p; }
};

template <class Exec>
void order_depth_first_radix(Exec& exec, Lbvh<Exec>& bvh) {
  const uint32_t n = bvh.num_leaves;
  if (n == 0) return;
  if (n == 1) return order_single_leaf(exec, bvh);
  // Build scratch that is free once the climb is done: keys in morton/morton_sorted, node
  // numbers in prim_iota and other_bound.
  exec.for_each_n(n - 1, DepthFirstKeyFn{bvh.build_first.data(), bvh.build_last.data(),
                                         bvh.morton.data(), bvh.prim_iota.data()});
  int leaf_bits = 1;
  while ((uint64_t(1) << leaf_bits) < n) ++leaf_bits;
  exec.sort_pairs(bvh.morton.data(), bvh.morton_sorted.data(), bvh.prim_iota.data(),
                  bvh.other_bound.data(), n - 1, 32 + leaf_bits, bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(n - 1, IndexFromSortedFn{bvh.other_bound.data(), bvh.new_index.data()});
  const DepthFirstLayout layout = depth_first_layout(bvh);
  exec.for_each_n(n - 1, ScatterNodesFn{layout, n});
  exec.for_each_n(n, LinkLeavesFn{layout, n});
  index_refit(exec, bvh);
}

}  // namespace cdb
