#pragma once
// Refit: new leaf boxes from the current vertices, then one thread per leaf climbs; the
// second thread to reach a node merges both children and goes on. Topology and depth-first
// order are kept.
//
// The climb is latency bound: each level is an atomic hand-over plus a load of the
// sibling's box, and an LBVH over a cloth is 20 to 60 levels deep. Leaves run in tiles, the
// treelets of at most kTile leaves (bvh/refit_index.h; one block on the GPU). A node whose
// leaves all lie in the climbing thread's tile is handed over in the tile's shared memory
// with block-scope atomics; only nodes spanning tiles (the top of the tree, above the
// treelets) pay for a device-scope atomic and an L2 load, or are left to RefitTopFn.
//
// In-tile slots: an internal node is identified by its split, the last leaf of its left
// child, unique among internal nodes; in-tile nodes have splits in [tile_first, tile_last),
// fewer than kTile.
//
// Spanning nodes count arrivals in refit_flag without a reset: every refit brings exactly
// two arrivals to each spanning node (a node's tile-spanning is fixed by the topology), so
// flags stay even between refits and the first arrival is the one that sees an even value.
// Lbvh::reserve (each build) zeroes the flags; restructures keep them even.
#include <algorithm>
#include <cstdint>

#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/refit_handover.h"
#include "cdbench/bvh/refit_levels.h"
#include "cdbench/bvh/refit_top.h"
#include "cdbench/core/atomics.h"
#include "cdbench/exec/tiles.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

struct RefitFn {
  static constexpr uint32_t kTile = kRefitTile;
  struct Shared {
    uint32_t arrived[kTile];
    float box[kTile][2][6];  // [split slot][left, right child]: lo xyz, hi xyz (handover_store)
  };

  MeshView mesh;
  TreeArrays tree;
  uint32_t* flag;
  bool stop_at_spanning;  // the spanning top is refitted by RefitTopFn (refit_top.h)
  CounterReset reset;     // zeroed by the first tile's first lanes

  CDB_HD void init(Shared& s, uint32_t lane) const { s.arrived[lane] = 0; }

  // A node's links and leaf range: written by the build, read-only here. Left and escape
  // go back into the box's link lanes (node_ref.h).
  struct Links {
    uint32_t left, right, parent, first, last, escape;
  };
  CDB_HD Links links(uint32_t k) const {
    if (k == kNoNode) return {kNoNode, kNoNode, kNoNode, 0, 0, kNoNode};
    return {tree.node_left[k], tree.node_right[k], tree.node_parent[k], tree.node_first[k], tree.node_last[k],
            tree.node_escape[k]};
  }

  // Each level's links are loaded together, one level ahead: the loads of the parent's
  // links go out before this level's hand-over and arrive while it waits, so a level costs
  // the hand-over and the sibling's box, not also a chain of topology loads.
  CDB_HD void operator()(uint32_t i, uint32_t tile_first, uint32_t tile_last, Shared& s) const {
    if (i < reset.count) reset.counters[i] = 0;
    vec4f lo, hi;
    const uint32_t prim = tree.leaf_prim[i], escape = tree.leaf_escape[i];
    face_box(mesh, prim, lo, hi);
    tree.leaf_box[i] = {{lo.x, lo.y, lo.z, link_lane(escape)}, {hi.x, hi.y, hi.z, link_lane(prim)}};
    uint32_t child = leaf_ref(i), first = i, last = i;  // the subtree climbed so far
    uint32_t p = tree.leaf_parent[i];
    Links at = links(p);
    while (p != kNoNode) {
      const bool from_left = at.left == child;
      const uint32_t p_first = from_left ? first : at.first;
      const uint32_t p_last = from_left ? at.last : last;
      const Links up = links(at.parent);
      vec4f slo, shi;
      if (tile_first <= p_first && p_last <= tile_last) {
        const uint32_t slot = (from_left ? last : first - 1) - tile_first;
        const int side = from_left ? 0 : 1;
        float* mine = s.box[slot][side];
        handover_store(&mine[0], lo.x), handover_store(&mine[1], lo.y), handover_store(&mine[2], lo.z);
        handover_store(&mine[3], hi.x), handover_store(&mine[4], hi.y), handover_store(&mine[5], hi.z);
        if (atomic_add_acq_rel_block(&s.arrived[slot], 1u) == 0) return;
        float* other = s.box[slot][1 - side];
        slo = {handover_load(&other[0]), handover_load(&other[1]), handover_load(&other[2]), 0};
        shi = {handover_load(&other[3]), handover_load(&other[4]), handover_load(&other[5]), 0};
      } else {
        if (stop_at_spanning) return;
        if (!span_handover(flag, p, from_left ? at.right : at.left, tree, slo, shi))
          return;
      }
      lo = min_xyz(lo, slo, link_lane(at.left));
      hi = max_xyz(hi, shi, link_lane(at.escape));
      tree.node_box[p] = {lo, hi};
      child = p;
      first = p_first;
      last = p_last;
      p = at.parent;
      at = up;
    }
  }
};

// Refits the tree, zeroing `reset` on the way; true if it did (not for a tree with fewer
// leaves than counters to zero: then the caller must).
template <class Exec>
bool refit(Exec& exec, Lbvh<Exec>& bvh, const MeshView& mesh, CounterReset reset = {}) {
  const uint32_t n = bvh.num_leaves;
  if (n < reset.count) reset = {};
  if (n == 0) return false;
  const bool top_in_block = bvh.refit_top_fits();
  const Tiles tiles{bvh.tile_first.data(), bvh.tile_count.data(), bvh.refit_tile_blocks()};
  const TreeArrays tree = bvh.tree();
  const RefitIndexArrays index = bvh.refit_index();
  if (bvh.refit_levels)
    exec.for_each_tile_in_phases(tiles, RefitLevelsFn{mesh, tree, index, bvh.refit_flag.data(), top_in_block, reset});
  else
    exec.for_each_tile(tiles, RefitFn{mesh, tree, bvh.refit_flag.data(), top_in_block, reset});
  if (top_in_block)
    exec.in_one_block(RefitTopFn{std::min(bvh.refit_top_shared_slots, RefitTopFn::kSharedSlots), index, tree});
  return reset.count > 0;
}

}  // namespace cdb
