#pragma once
// The refit's tiles level by level (--refit-levels): each tile, a treelet of at most
// kRefitTile leaves (bvh/refit_index.h), is one block whose threads merge the treelet's
// nodes deepest level first, one block barrier between levels, every box handed over in
// shared memory. The climb of bvh/refit.h instead hands each node to the second of its
// children's threads to arrive, through a block-scope atomic, and loads the node's links
// from global memory one level ahead: its surviving threads halve with every level while
// the block holds its slots, and each level waits on gathered loads (the 1M cloth's tile
// kernel ran at 42% occupancy, half its stalls on L1TEX). Here every link a tile needs is
// loaded once, at the start, from tables laid out by split: thread t of a tile owns the
// internal node whose split (the last leaf of its left child) is the tile's leaf t, and
// the tables give its node, its links, its depth in the treelet and its children's places
// in shared memory, in loads that are coalesced and independent of each other. Min and max
// are exact, so the boxes equal the climb's bit for bit.
//
// Above the treelets the tile's root climbs on as in bvh/refit.h (a device-scope hand-over
// per spanning node), or stops there for RefitTopFn.
#include <cstdint>

#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/refit_handover.h"
#include "cdbench/bvh/refit_tiles.h"
#include "cdbench/core/atomics.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

// A tile-local child place: its slot in the tile (leaf t, or the node whose split is leaf t)
// and whether it is a leaf. Ten bits each for the depth and both children.
inline constexpr uint32_t kLevelSlotBits = 10;
inline constexpr uint32_t kLevelLeaf = 1u << (kLevelSlotBits - 1);
inline constexpr uint32_t kLevelMask = (1u << kLevelSlotBits) - 1;
static_assert(kRefitTile <= kLevelLeaf, "a tile's slots must fit below the leaf bit");

CDB_HD_INLINE uint32_t level_depth(uint32_t code) { return code & kLevelMask; }
CDB_HD_INLINE uint32_t level_child(uint32_t code, int side) {
  return (code >> (kLevelSlotBits * (side + 1))) & kLevelMask;
}

// The split of internal node k: the last leaf of its left child.
CDB_HD_INLINE uint32_t node_split(const TreeArrays& tree, uint32_t k) {
  const uint32_t left = tree.node_left[k];
  return is_leaf(left) ? ref_index(left) : tree.node_last[left];
}

// Over internal nodes k, after RefitTablesFn: for each node inside a treelet, at its split,
// the node and its code (depth below the treelet's root, children's tile-local places).
// The splits of a treelet of L leaves are its first L - 1 leaves, one node each; the last
// leaf of a treelet is the split of a spanning node (or of none) and keeps no entry.
struct RefitLevelsIndexFn {
  TreeArrays tree;
  RefitIndexArrays index;  // writes level_node, level_code and level_link (bvh/tree_arrays.h)
  CDB_HD uint32_t place(uint32_t child, uint32_t first) const {
    return is_leaf(child) ? (ref_index(child) - first) | kLevelLeaf : node_split(tree, child) - first;
  }
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t lo = tree.node_first[k];
    if (spans_tiles(lo, tree.node_last[k])) return;
    uint32_t depth = 0;
    for (uint32_t a = tree.node_parent[k]; a != kNoNode && !spans_tiles(tree.node_first[a], tree.node_last[a]);
         a = tree.node_parent[a])
      ++depth;
    const uint32_t first = index.tile_first[index.tile_scan[lo] + index.tile_start[lo] - 1];
    const uint32_t split = node_split(tree, k);
    index.level_node[split] = k;
    index.level_link[2 * size_t(split)] = tree.node_left[k];
    index.level_link[2 * size_t(split) + 1] = tree.node_escape[k];
    index.level_code[split] = depth | place(tree.node_left[k], first) << kLevelSlotBits |
                              place(tree.node_right[k], first) << (2 * kLevelSlotBits);
  }
};

// Phases of one tile (Exec::for_each_tile_in_phases): phase 0 makes the leaves' boxes and
// loads the tile's table; phase 1 + m merges the nodes at depth D - m (D the deepest).
struct RefitLevelsFn {
  static constexpr uint32_t kTile = kRefitTile;
  struct Shared {
    float leaf[kTile][6];  // lo xyz, hi xyz
    float node[kTile][6];  // by split slot
    uint32_t code[kTile];
    uint32_t node_id[kTile];
    float left_lane[kTile];  // link lanes of the node's box (node_ref.h)
    float escape_lane[kTile];
    uint32_t phases;  // deepest depth + 2; 0 for a tile of one leaf
  };

  MeshView mesh;
  TreeArrays tree;
  RefitIndexArrays index;  // its level tables
  uint32_t* flag;
  bool stop_at_spanning;  // the spanning top is refitted by RefitTopFn (refit_top.h)
  CounterReset reset;     // zeroed by the first tile's first lanes

  CDB_HD void init(Shared& s, uint32_t lane) const {
    if (lane == 0) s.phases = 0;
  }
  CDB_HD uint32_t phases(const Shared& s) const { return s.phases > 1 ? s.phases : 1; }

  CDB_HD void phase(uint32_t p, uint32_t lane, uint32_t first, uint32_t last, Shared& s) const {
    const uint32_t i = first + lane;
    if (p == 0) {
      if (i < reset.count) reset.counters[i] = 0;
      if (i > last) return;
      vec4f lo, hi;
      const uint32_t prim = tree.leaf_prim[i];
      face_box(mesh, prim, lo, hi);
      tree.leaf_box[i] = {{lo.x, lo.y, lo.z, link_lane(tree.leaf_escape[i])}, {hi.x, hi.y, hi.z, link_lane(prim)}};
      put(s.leaf[lane], lo, hi);
      if (i < last) {
        const uint32_t k = index.level_node[i], code = index.level_code[i];
        s.code[lane] = code;
        s.node_id[lane] = k;
        s.left_lane[lane] = link_lane(index.level_link[2 * size_t(i)]);
        s.escape_lane[lane] = link_lane(index.level_link[2 * size_t(i) + 1]);
        atomic_max_relaxed(&s.phases, level_depth(code) + 2);
      } else if (first == last && !stop_at_spanning) {
        climb(leaf_ref(i), tree.leaf_parent[i], lo, hi);
      }
      return;
    }
    if (i >= last) return;
    const uint32_t code = s.code[lane], depth = s.phases - 1 - p;
    if (level_depth(code) != depth) return;
    vec4f lo, hi, olo, ohi;
    get(s, level_child(code, 0), lo, hi);
    get(s, level_child(code, 1), olo, ohi);
    lo = min_xyz(lo, olo, s.left_lane[lane]);
    hi = max_xyz(hi, ohi, s.escape_lane[lane]);
    put(s.node[lane], lo, hi);
    const uint32_t k = s.node_id[lane];
    tree.node_box[k] = {lo, hi};
    if (depth == 0 && !stop_at_spanning) climb(k, tree.node_parent[k], lo, hi);
  }

  CDB_HD_INLINE static void put(float (&b)[6], const vec4f& lo, const vec4f& hi) {
    b[0] = lo.x, b[1] = lo.y, b[2] = lo.z, b[3] = hi.x, b[4] = hi.y, b[5] = hi.z;
  }
  CDB_HD_INLINE static void get(const Shared& s, uint32_t place, vec4f& lo, vec4f& hi) {
    const float(&b)[6] = place & kLevelLeaf ? s.leaf[place & (kLevelLeaf - 1)] : s.node[place];
    lo = {b[0], b[1], b[2], 0};
    hi = {b[3], b[4], b[5], 0};
  }

  // From a treelet's root (node or leaf `child`, box lo/hi) up through the spanning nodes:
  // the second arrival at each merges and goes on.
  CDB_HD void climb(uint32_t child, uint32_t p, vec4f lo, vec4f hi) const {
    while (p != kNoNode) {
      const uint32_t left = tree.node_left[p], right = tree.node_right[p], up = tree.node_parent[p],
                     escape = tree.node_escape[p];
      vec4f slo, shi;
      if (!span_handover(flag, p, left == child ? right : left, tree, slo, shi)) return;
      lo = min_xyz(lo, slo, link_lane(left));
      hi = max_xyz(hi, shi, link_lane(escape));
      tree.node_box[p] = {lo, hi};
      child = p;
      p = up;
    }
  }
};

}  // namespace cdb
