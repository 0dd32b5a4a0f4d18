#pragma once
// The refit's tiles: treelets, the largest subtrees of at most kRefitTile leaves. A tile is
// one block of the refit's tile kernel (bvh/refit.h), whose nodes hand over in shared
// memory; only the nodes above the treelets (more than kRefitTile leaves, spans_tiles) pay
// for a hand-over between blocks, or for a level of the top refitted in one block
// (bvh/refit_top.h). Tiles of kRefitTile consecutive leaves left a chain of spanning nodes
// along every tile boundary, nearly as deep as the tree (funnel 17 of 19 levels, the 32K
// cloth 19 of 20); treelets leave only the top of the tree (funnel 5 levels, the 32K cloth 8)
// for 1.6 times as many tiles (docs/design.md).
//
// In the depth-first layout a subtree's leaves are consecutive, so the treelets cut the
// leaves into ranges: tile t is [tile_first[t], tile_first[t + 1]), tile_count[0] of them.
// Indexed once per topology (index_refit: after every build, order and restructure).
#include <cstdint>

#include "bvh/lbvh.h"
#include "bvh/node_ref.h"
#include "bvh/refit_top.h"

namespace cdb {

// Marks the first leaf of every treelet: of each internal treelet root, and of each leaf
// hanging from a spanning node (a treelet of one leaf).
struct TreeletStartFn {
  const uint32_t* node_first;
  const uint32_t* node_last;
  const uint32_t* node_left;
  const uint32_t* node_right;
  const uint32_t* node_parent;
  uint32_t* start;  // per leaf, zeroed: 1 where a treelet starts
  CDB_HD void operator()(uint32_t k) const {
    if (!spans_tiles(node_first[k], node_last[k])) {
      const uint32_t p = node_parent[k];
      if (p == kNoNode || spans_tiles(node_first[p], node_last[p])) start[node_first[k]] = 1;
      return;
    }
    if (is_leaf(node_left[k])) start[ref_index(node_left[k])] = 1;
    if (is_leaf(node_right[k])) start[ref_index(node_right[k])] = 1;
  }
};

// After the exclusive scan of the marks: leaf l's treelet is scan[l].
struct TreeletFirstFn {
  const uint32_t* start;
  const uint32_t* scan;
  uint32_t* tile_first;
  CDB_HD void operator()(uint32_t l) const {
    if (start[l]) tile_first[scan[l]] = l;
  }
};

struct TreeletCountFn {
  const uint32_t* start;
  const uint32_t* scan;
  uint32_t n;
  uint32_t* tile_first;
  uint32_t* tile_count;
  CDB_HD void operator()(uint32_t) const {
    const uint32_t count = scan[n - 1] + start[n - 1];
    tile_count[0] = count;
    tile_first[count] = n;
  }
};

template <class Exec>
void index_treelets(Exec& exec, Lbvh<Exec>& bvh) {
  const uint32_t n = bvh.num_leaves;
  if (n == 0) return;
  exec.fill(bvh.tile_start.data(), n, 0u);
  if (n == 1)
    exec.fill(bvh.tile_start.data(), 1, 1u);
  else
    exec.for_each_n(n - 1, TreeletStartFn{bvh.node_first.data(), bvh.node_last.data(), bvh.node_left.data(),
                                          bvh.node_right.data(), bvh.node_parent.data(), bvh.tile_start.data()});
  exec.exclusive_scan(bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(n, TreeletFirstFn{bvh.tile_start.data(), bvh.tile_scan.data(), bvh.tile_first.data()});
  exec.for_each_n(1, TreeletCountFn{bvh.tile_start.data(), bvh.tile_scan.data(), n, bvh.tile_first.data(),
                                    bvh.tile_count.data()});
}

// What a refit needs per topology, after every build, order and restructure: the treelet
// tiles, and the spanning top's index where it refits in one block.
template <class Exec>
void index_refit(Exec& exec, Lbvh<Exec>& bvh) {
  index_treelets(exec, bvh);
  index_spanning_nodes(exec, bvh);
}

}  // namespace cdb
