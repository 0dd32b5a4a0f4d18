#pragma once
// What a refit needs per topology, indexed after every build, order and restructure
// (index_refit): its tiles, and the spanning top's slots where the top refits in one block.
//
// The tiles are treelets, the largest subtrees of at most kRefitTile leaves. A tile is one
// block of the refit's tile kernel (bvh/refit.h), whose nodes hand over in shared memory;
// only the nodes above the treelets (more than kRefitTile leaves, spans_tiles) pay for a
// hand-over between blocks, or for a level of the top refitted in one block
// (bvh/refit_top.h). Tiles of kRefitTile consecutive leaves left a chain of spanning nodes
// along every tile boundary, nearly as deep as the tree (funnel 17 of 19 levels, the 32K
// cloth 19 of 20); treelets leave only the top of the tree (funnel 5 levels, the 32K cloth
// 8), for 1.6 times as many tiles (docs/design.md). In the depth-first layout a subtree's
// leaves are consecutive, so the treelets cut the leaves into ranges: tile t is
// [tile_first[t], tile_first[t + 1]), tile_count[0] of them.
//
// The top's slots: compact slots 0..S-1 for the spanning nodes in node order, each with its
// node, its depth, its parent's slot and side, and its children that do not span.
//
// Four launches when both scans fit one block (CudaExec::exclusive_scan_pair): marks, the
// scans, the counts, the tables; a fifth, the level tables, for --refit-levels.
#include <cstdint>

#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/refit_levels.h"
#include "cdbench/core/atomics.h"

namespace cdb {

// Over internal nodes: which leaves start a treelet and, where the top is indexed, which
// nodes span. Every leaf but the first starts the right child of exactly one node (the one
// whose split it follows), and starts a treelet exactly when that node spans: then the
// treelet holding it lies below the node, on the right child's leftmost path; else the
// node, with leaves before it, lies inside the treelet. The first leaf always starts one.
// So every mark is written once, and no fill comes first.
struct RefitMarksFn {
  const uint32_t* node_first;
  const uint32_t* node_last;
  const uint32_t* node_right;
  uint32_t last_leaf;
  uint32_t* tile_start;  // per leaf: 1 where a treelet starts
  uint32_t* span_flag;   // per internal node: 1 where it spans; null when the top is not indexed
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t first = node_first[k], last = node_last[k];
    const bool spans = spans_tiles(first, last);
    if (span_flag) span_flag[k] = spans ? 1u : 0u;
    const uint32_t r = node_right[k];
    tile_start[is_leaf(r) ? ref_index(r) : node_first[r]] = spans ? 1u : 0u;
    if (first == 0 && last == last_leaf) tile_start[0] = 1u;
  }
};

// After the scans: the number of tiles (and n after the last tile's first leaf) and, where
// the top is indexed, of slots, with the deepest slot's depth zeroed for RefitTablesFn to
// raise.
struct RefitCountsFn {
  const uint32_t* tile_start;
  const uint32_t* tile_scan;
  uint32_t n;
  uint32_t* tile_first;
  uint32_t* tile_count;
  const uint32_t* span_flag;  // null when the top is not indexed
  const uint32_t* span_scan;
  uint32_t* span_count;  // [0]: slots, [1]: the deepest slot's depth
  CDB_HD void operator()(uint32_t) const {
    const uint32_t tiles = tile_scan[n - 1] + tile_start[n - 1];
    tile_count[0] = tiles;
    tile_first[tiles] = n;
    if (!span_flag) return;
    span_count[0] = span_scan[n - 2] + span_flag[n - 2];
    span_count[1] = 0;
  }
};

// Over leaves l, and internal node l where the top is indexed: each treelet's first leaf,
// each spanning node's slot.
struct RefitTablesFn {
  const uint32_t* tile_start;
  const uint32_t* tile_scan;
  uint32_t* tile_first;
  uint32_t internal;  // internal nodes, 0 when the top is not indexed
  const uint32_t* node_first;
  const uint32_t* node_last;
  const uint32_t* node_left;
  const uint32_t* node_right;
  const uint32_t* node_parent;
  const uint32_t* span_scan;  // the slot of spanning node k
  uint32_t* span_node;        // per slot: its node
  uint32_t* span_parent;      // per slot: parent slot | side << 31 (1: right child), kNoNode at the root
  uint32_t* span_child;       // per slot, left and right: the child if it does not span, else kNoNode
  uint32_t* span_depth;       // per slot: its node's depth, the root's 0
  uint32_t* max_depth;        // zeroed by RefitCountsFn
  CDB_HD void operator()(uint32_t l) const {
    if (tile_start[l]) tile_first[tile_scan[l]] = l;
    if (l >= internal) return;
    const uint32_t k = l;
    if (!spans_tiles(node_first[k], node_last[k])) return;
    const uint32_t s = span_scan[k];
    span_node[s] = k;
    const uint32_t p = node_parent[k];
    // Every ancestor of a spanning node spans: its depth in the tree is its depth in the top,
    // a few levels over treelets.
    uint32_t depth = 0;
    for (uint32_t a = p; a != kNoNode; a = node_parent[a]) ++depth;
    span_depth[s] = depth;
    atomic_max_relaxed(max_depth, depth);
    span_parent[s] = p == kNoNode ? kNoNode : span_scan[p] | (node_left[p] == k ? 0u : kLeafBit);
    const uint32_t child[2] = {node_left[k], node_right[k]};
    for (int side = 0; side < 2; ++side) {
      const uint32_t c = child[side];
      span_child[2 * s + side] = !is_leaf(c) && spans_tiles(node_first[c], node_last[c]) ? kNoNode : c;
    }
  }
};

template <class Exec>
void index_refit(Exec& exec, Lbvh<Exec>& bvh) {
  const uint32_t n = bvh.num_leaves;
  if (n == 0) return;
  const bool top = bvh.refit_top_fits();
  uint32_t* span_flag = top ? bvh.span_flag.data() : nullptr;
  if (n == 1)
    exec.fill(bvh.tile_start.data(), 1, 1u);
  else
    exec.for_each_n(n - 1, RefitMarksFn{bvh.node_first.data(), bvh.node_last.data(), bvh.node_right.data(), n - 1,
                                        bvh.tile_start.data(), span_flag});
  if (top)
    exec.exclusive_scan_pair(bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.span_flag.data(),
                             bvh.span_scan.data(), n - 1, bvh.temp.data(), bvh.temp.size());
  else
    exec.exclusive_scan(bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(1, RefitCountsFn{bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.tile_first.data(),
                                   bvh.tile_count.data(), span_flag, bvh.span_scan.data(), bvh.span_count.data()});
  exec.for_each_n(n, RefitTablesFn{bvh.tile_start.data(), bvh.tile_scan.data(), bvh.tile_first.data(),
                                   top ? n - 1 : 0, bvh.node_first.data(), bvh.node_last.data(), bvh.node_left.data(),
                                   bvh.node_right.data(), bvh.node_parent.data(), bvh.span_scan.data(),
                                   bvh.span_node.data(), bvh.span_parent.data(), bvh.span_child.data(),
                                   bvh.span_depth.data(), bvh.span_count.data() + 1});
  if (bvh.refit_levels && n > 1)
    exec.for_each_n(n - 1, RefitLevelsIndexFn{bvh.node_left.data(), bvh.node_right.data(), bvh.node_parent.data(),
                                              bvh.node_escape.data(), bvh.node_first.data(), bvh.node_last.data(),
                                              bvh.tile_start.data(), bvh.tile_scan.data(), bvh.tile_first.data(),
                                              bvh.level_node.data(), bvh.level_code.data(), bvh.level_link.data()});
}

}  // namespace cdb
