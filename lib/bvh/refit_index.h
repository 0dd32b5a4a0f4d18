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
  TreeArrays tree;
  RefitIndexArrays index;  // writes tile_start and, unless null, span_flag
  uint32_t last_leaf;
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t first = tree.node_first[k], last = tree.node_last[k];
    const bool spans = spans_tiles(first, last);
    if (index.span_flag) index.span_flag[k] = spans ? 1u : 0u;
    const uint32_t r = tree.node_right[k];
    index.tile_start[is_leaf(r) ? ref_index(r) : tree.node_first[r]] = spans ? 1u : 0u;
    if (first == 0 && last == last_leaf) index.tile_start[0] = 1u;
  }
};

// After the scans: the number of tiles (and n after the last tile's first leaf) and, where
// the top is indexed, of slots, with the deepest slot's depth zeroed for RefitTablesFn to
// raise.
struct RefitCountsFn {
  RefitIndexArrays index;  // span_flag null: the top is not indexed
  uint32_t n;
  CDB_HD void operator()(uint32_t) const {
    const uint32_t tiles = index.tile_scan[n - 1] + index.tile_start[n - 1];
    index.tile_count[0] = tiles;
    index.tile_first[tiles] = n;
    if (!index.span_flag) return;
    index.span_count[0] = index.span_scan[n - 2] + index.span_flag[n - 2];
    index.span_count[1] = 0;
  }
};

// Over leaves l, and internal node l where the top is indexed: each treelet's first leaf,
// each spanning node's slot.
struct RefitTablesFn {
  TreeArrays tree;
  RefitIndexArrays index;  // writes tile_first and the slots; raises span_count[1], zeroed by
                           // RefitCountsFn, to the deepest slot's depth
  uint32_t internal;  // internal nodes, 0 when the top is not indexed
  CDB_HD void operator()(uint32_t l) const {
    if (index.tile_start[l]) index.tile_first[index.tile_scan[l]] = l;
    if (l >= internal) return;
    const uint32_t k = l;
    if (!spans_tiles(tree.node_first[k], tree.node_last[k])) return;
    const uint32_t s = index.span_scan[k];
    index.span_node[s] = k;
    const uint32_t p = tree.node_parent[k];
    // Every ancestor of a spanning node spans: its depth in the tree is its depth in the top,
    // a few levels over treelets.
    uint32_t depth = 0;
    for (uint32_t a = p; a != kNoNode; a = tree.node_parent[a]) ++depth;
    index.span_depth[s] = depth;
    atomic_max_relaxed(index.span_count + 1, depth);
    index.span_parent[s] = p == kNoNode ? kNoNode : index.span_scan[p] | (tree.node_left[p] == k ? 0u : kLeafBit);
    const uint32_t child[2] = {tree.node_left[k], tree.node_right[k]};
    for (int side = 0; side < 2; ++side) {
      const uint32_t c = child[side];
      index.span_child[2 * s + side] = !is_leaf(c) && spans_tiles(tree.node_first[c], tree.node_last[c]) ? kNoNode : c;
    }
  }
};

template <class Exec>
void index_refit(Exec& exec, Lbvh<Exec>& bvh) {
  const uint32_t n = bvh.num_leaves;
  if (n == 0) return;
  const bool top = bvh.refit_top_fits();
  const TreeArrays tree = bvh.tree();
  const RefitIndexArrays index = bvh.refit_index();
  if (n == 1)
    exec.fill(bvh.tile_start.data(), 1, 1u);
  else
    exec.for_each_n(n - 1, RefitMarksFn{tree, index, n - 1});
  if (top)
    exec.exclusive_scan_pair(bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.span_flag.data(),
                             bvh.span_scan.data(), n - 1, bvh.temp.data(), bvh.temp.size());
  else
    exec.exclusive_scan(bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(1, RefitCountsFn{index, n});
  exec.for_each_n(n, RefitTablesFn{tree, index, top ? n - 1 : 0});
  if (bvh.refit_levels && n > 1) exec.for_each_n(n - 1, RefitLevelsIndexFn{tree, index});
}

}  // namespace cdb
