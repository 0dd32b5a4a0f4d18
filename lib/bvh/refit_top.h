#pragma once
// The top of the refit in one block. refit.h climbs in tiles, the treelets
// (bvh/refit_index.h); nodes above them ("spanning nodes", the top of the tree) cost a
// device-scope atomic and an L2 load each in the tile kernel (docs/design.md "Constants
// and their measurements"). With the top in one block the tile kernel stops below them and
// one block of threads refits all of them, their boxes, parent links and depths in shared
// memory.
//
// The block refits the top level by level, deepest first, one block barrier between
// levels: every spanning node at depth d merges both sides of its slot (its children, at
// depth d + 1 or below the top, are final) and puts the merge on its side of the parent.
// No atomics and no arrival bits: the barriers order every hand-over, which
// compute-sanitizer's racecheck follows. A level cost as much as in the climb with
// acquire-release arrivals it replaced; what made the top cheap is having fewer levels over
// treelets than over fixed tiles (docs/design.md "Constants and their measurements").
//
// The spanning nodes are indexed once per topology (bvh/refit_index.h, after every build,
// order and restructure): compact slots 0..S-1, each slot's node, its depth (every
// ancestor of a spanning node spans, so its depth in the tree is its depth in the top), its
// parent's slot with the side it hangs on, and its children that do not span, whose boxes
// the tile kernel wrote. Slots from Lbvh::refit_top_shared_slots on keep their boxes and
// links in global memory instead (the barrier orders those too): slower, never wrong.
#include <cstdint>

#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/tree_arrays.h"

namespace cdb {

// One block: phase 0 loads the slots' links and depths into shared memory and the
// non-spanning children's boxes onto their sides; phase 1 + i merges the slots at depth
// D - i (D the deepest), keeps each merge on side 0 of its slot and puts it on its side of
// the parent; the last phase writes every slot's box.
struct RefitTopFn {
  // 84 bytes a slot (over treelets funnel's 8.7K leaves have 26 spanning nodes, cloth-wave's
  // 32K 103).
  static constexpr uint32_t kSharedSlots = kRefitTopSharedSlots;
  struct Shared {
    vec4f lo[kSharedSlots][2];  // [slot][side]: the child's box on that side (lanes x, y, z)
    vec4f hi[kSharedSlots][2];
    uint32_t parent[kSharedSlots];
    uint32_t depth[kSharedSlots];
    uint32_t node[kSharedSlots];
    float left_lane[kSharedSlots];  // link lanes of the node's box (node_ref.h)
    float escape_lane[kSharedSlots];
    uint32_t count, deepest;  // span_count, read once
  };

  static_assert(sizeof(Shared) <= 227 * 1024, "more shared memory than a Hopper block can take");

  uint32_t shared_slots;  // slots below this are in shared memory (at most kSharedSlots)
  RefitIndexArrays index;  // the slots; span_lo and span_hi hold those past shared_slots
  TreeArrays tree;

  CDB_HD uint32_t phases() const { return index.span_count[1] + 3; }

  CDB_HD void phase(uint32_t p, uint32_t t, uint32_t threads, Shared& sh) const {
    if (p == 0) {
      const uint32_t count = index.span_count[0];
      const uint32_t in_shared = count < shared_slots ? count : shared_slots;
      if (t == 0) sh.count = count, sh.deepest = index.span_count[1];
      // Loads only, independent of each other, so many are in flight at once.
      for (uint32_t s = t; s < in_shared; s += threads) {
        const uint32_t k = index.span_node[s];
        sh.parent[s] = index.span_parent[s];
        sh.depth[s] = index.span_depth[s];
        sh.node[s] = k;
        sh.left_lane[s] = link_lane(tree.node_left[k]);
        sh.escape_lane[s] = link_lane(tree.node_escape[k]);
      }
#if defined(__CUDA_ARCH__)
#pragma unroll 4
#endif
      for (uint32_t e = t; e < 2 * count; e += threads) {
        const uint32_t c = index.span_child[e];
        if (c == kNoNode) continue;
        const NodeBox b = is_leaf(c) ? tree.leaf_box[ref_index(c)] : tree.node_box[c];
        put(e / 2, e % 2, b.lo, b.hi, sh);
      }
      return;
    }
    const uint32_t count = sh.count;
    if (p == sh.deepest + 2) {
      // The write-back, from side 0 of every slot: writing each box in its level instead
      // measured slower (docs/experiments.md).
      for (uint32_t s = t; s < count; s += threads) {
        const bool local = s < shared_slots;
        vec4f lo, hi;
        get(s, 0, lo, hi, sh);
        const uint32_t k = local ? sh.node[s] : index.span_node[s];
        tree.node_box[k] = {{lo.x, lo.y, lo.z, local ? sh.left_lane[s] : link_lane(tree.node_left[k])},
                            {hi.x, hi.y, hi.z, local ? sh.escape_lane[s] : link_lane(tree.node_escape[k])}};
      }
      return;
    }
    const uint32_t depth = sh.deepest - (p - 1);
    for (uint32_t s = t; s < count; s += threads) {
      const bool local = s < shared_slots;
      if ((local ? sh.depth[s] : index.span_depth[s]) != depth) continue;
      vec4f lo, hi, olo, ohi;
      get(s, 0, lo, hi, sh);
      get(s, 1, olo, ohi, sh);
      lo = min_xyz(lo, olo, 0);
      hi = max_xyz(hi, ohi, 0);
      put(s, 0, lo, hi, sh);
      const uint32_t up = local ? sh.parent[s] : index.span_parent[s];
      if (up != kNoNode) put(ref_index(up), is_leaf(up) ? 1u : 0u, lo, hi, sh);
    }
  }

  // A box on side `side` of slot s.
  CDB_HD void put(uint32_t s, uint32_t side, const vec4f& lo, const vec4f& hi, Shared& sh) const {
    if (s < shared_slots) {
      sh.lo[s][side] = lo;
      sh.hi[s][side] = hi;
    } else {
      index.span_lo[2 * size_t(s) + side] = lo;
      index.span_hi[2 * size_t(s) + side] = hi;
    }
  }
  CDB_HD void get(uint32_t s, uint32_t side, vec4f& lo, vec4f& hi, const Shared& sh) const {
    if (s < shared_slots) {
      lo = sh.lo[s][side];
      hi = sh.hi[s][side];
    } else {
      lo = index.span_lo[2 * size_t(s) + side];
      hi = index.span_hi[2 * size_t(s) + side];
    }
  }
};

}  // namespace cdb
