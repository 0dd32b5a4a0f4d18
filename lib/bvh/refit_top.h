#pragma once
// The top of the refit in one block. refit.h climbs in tiles of kRefitTile leaves; nodes
// whose leaves span tiles ("spanning nodes", the top of the tree) cost a device-scope atomic
// and an L2 load each in the tile kernel, and they are most of the deepest path
// (docs/design.md "Constants and their measurements"). With the top in one block the
// tile kernel stops below them and one block of threads refits all of them, with their
// boxes, arrival bits and parent links in shared memory: a level is a shared-memory atomic
// and a shared-memory load.
//
// The spanning nodes are indexed once per topology (index_spanning_nodes, after every
// build, order and restructure): compact slots 0..S-1, each slot's node, its parent's slot
// (with the side it hangs on), and its children that do not span, where the block's climbs
// start. Slots from Lbvh::refit_top_shared_slots on keep their boxes and arrival bits in global
// memory instead, still with block-scope hand-overs: slower, never wrong.
#include <cstdint>

#include "bvh/lbvh.h"
#include "bvh/node_ref.h"
#include "core/atomics.h"

namespace cdb {

// Whether node [first, last] has leaves in two tiles.
CDB_HD_INLINE bool spans_tiles(uint32_t first, uint32_t last) { return first / kRefitTile != last / kRefitTile; }

struct SpanFlagFn {
  const uint32_t* node_first;
  const uint32_t* node_last;
  uint32_t* flag;
  CDB_HD void operator()(uint32_t k) const { flag[k] = spans_tiles(node_first[k], node_last[k]) ? 1u : 0u; }
};

// After the exclusive scan of the flags: the slot of node k is scan[k].
struct SpanSlotsFn {
  const uint32_t* node_first;
  const uint32_t* node_last;
  const uint32_t* node_left;
  const uint32_t* node_right;
  const uint32_t* node_parent;
  const uint32_t* scan;
  uint32_t* span_node;    // per slot: its node
  uint32_t* span_parent;  // per slot: parent slot | side << 31 (1: right child), kNoNode at the root
  uint32_t* span_child;   // per slot, left and right: the child if it does not span, else kNoNode
  CDB_HD void operator()(uint32_t k) const {
    if (!spans_tiles(node_first[k], node_last[k])) return;
    const uint32_t s = scan[k];
    span_node[s] = k;
    const uint32_t p = node_parent[k];
    span_parent[s] = p == kNoNode ? kNoNode : scan[p] | (node_left[p] == k ? 0u : kLeafBit);
    const uint32_t child[2] = {node_left[k], node_right[k]};
    for (int side = 0; side < 2; ++side) {
      const uint32_t c = child[side];
      span_child[2 * s + side] = !is_leaf(c) && spans_tiles(node_first[c], node_last[c]) ? kNoNode : c;
    }
  }
};

// S: the last node's slot plus its flag.
struct SpanCountFn {
  const uint32_t* scan;
  const uint32_t* flag;
  uint32_t last;
  uint32_t* count;
  CDB_HD void operator()(uint32_t) const { *count = scan[last] + flag[last]; }
};

template <class Exec>
void index_spanning_nodes(Exec& exec, Lbvh<Exec>& bvh) {
  if (!bvh.refit_top_fits()) return;
  const uint32_t internal = bvh.num_leaves - 1;
  exec.for_each_n(internal, SpanFlagFn{bvh.node_first.data(), bvh.node_last.data(), bvh.span_flag.data()});
  exec.exclusive_scan(bvh.span_flag.data(), bvh.span_scan.data(), internal, bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(1, SpanCountFn{bvh.span_scan.data(), bvh.span_flag.data(), internal - 1, bvh.span_count.data()});
  exec.for_each_n(internal, SpanSlotsFn{bvh.node_first.data(), bvh.node_last.data(), bvh.node_left.data(),
                                        bvh.node_right.data(), bvh.node_parent.data(), bvh.span_scan.data(),
                                        bvh.span_node.data(), bvh.span_parent.data(), bvh.span_child.data()});
  // From here on span_flag holds the arrival bits of the slots kept in global memory: zero
  // now, and every refit toggles each bit twice, so it is zero between refits.
  exec.fill(bvh.span_flag.data(), internal, 0u);
}

// One block, three phases separated by block barriers (Exec::in_one_block): parent links
// into shared memory; the climbs; the write-back of every spanning node's box.
struct RefitTopFn {
  // 52 bytes a slot (funnel's 8.7K leaves have 313 spanning nodes, cloth-wave's 32K 995).
  static constexpr uint32_t kSharedSlots = kRefitTopSharedSlots;
  static constexpr int kPhases = 3;
  struct Shared {
    float box[kSharedSlots][2][6];  // [slot][side]: lo xyz, hi xyz; after both arrivals [0] is the merge
    uint32_t parent[kSharedSlots];
    uint32_t arrived[kSharedSlots / 32];
  };

  static_assert(sizeof(Shared) <= 227 * 1024, "more shared memory than a Hopper block can take");

  uint32_t shared_slots;  // slots below this are in shared memory (at most kSharedSlots)
  const uint32_t* span_count;
  const uint32_t* span_node;
  const uint32_t* span_parent;
  const uint32_t* span_child;
  uint32_t* span_arrived;  // arrival bits of the slots past shared_slots
  vec4f* span_lo;          // their boxes, [2 * slot + side]
  vec4f* span_hi;
  const vec4f* leaf_lo;
  const vec4f* leaf_hi;
  const uint32_t* node_left;  // link lanes of the written boxes (node_ref.h)
  const uint32_t* node_escape;
  vec4f* node_lo;
  vec4f* node_hi;

  CDB_HD void phase(int p, uint32_t t, uint32_t threads, Shared& sh) const {
    const uint32_t count = *span_count;
    const uint32_t in_shared = count < shared_slots ? count : shared_slots;
    if (p == 0) {
      // Loads only, independent of each other, so many are in flight at once: the parent
      // links and the boxes of the non-spanning children, put on their sides of the slots.
      for (uint32_t s = t; s < in_shared; s += threads) sh.parent[s] = span_parent[s];
      for (uint32_t w = t; w < kSharedSlots / 32; w += threads) sh.arrived[w] = 0u;
#if defined(__CUDA_ARCH__)
#pragma unroll 4
#endif
      for (uint32_t e = t; e < 2 * count; e += threads) {
        const uint32_t c = span_child[e];
        if (c == kNoNode) continue;
        const vec4f lo = is_leaf(c) ? leaf_lo[ref_index(c)] : node_lo[c];
        const vec4f hi = is_leaf(c) ? leaf_hi[ref_index(c)] : node_hi[c];
        put(e / 2, e % 2, lo, hi, sh);
      }
    } else if (p == 1) {
      for (uint32_t e = t; e < 2 * count; e += threads)
        if (span_child[e] != kNoNode) climb(e / 2, e % 2, sh);
    } else {
      for (uint32_t s = t; s < count; s += threads) {
        const uint32_t k = span_node[s];
        const float left = link_lane(node_left[k]), escape = link_lane(node_escape[k]);
        if (s < shared_slots) {
          const float* b = sh.box[s][0];
          node_lo[k] = {b[0], b[1], b[2], left};
          node_hi[k] = {b[3], b[4], b[5], escape};
        } else {
          const vec4f lo = span_lo[2 * size_t(s)], hi = span_hi[2 * size_t(s)];
          node_lo[k] = {lo.x, lo.y, lo.z, left};
          node_hi[k] = {hi.x, hi.y, hi.z, escape};
        }
      }
    }
  }

  // A box on side `side` of slot s.
  CDB_HD void put(uint32_t s, uint32_t side, const vec4f& lo, const vec4f& hi, Shared& sh) const {
    if (s < shared_slots) {
      float* b = sh.box[s][side];
      handover_store(&b[0], lo.x), handover_store(&b[1], lo.y), handover_store(&b[2], lo.z);
      handover_store(&b[3], hi.x), handover_store(&b[4], hi.y), handover_store(&b[5], hi.z);
    } else {
      span_lo[2 * size_t(s) + side] = lo;
      span_hi[2 * size_t(s) + side] = hi;
    }
  }
  CDB_HD void get(uint32_t s, uint32_t side, vec4f& lo, vec4f& hi, Shared& sh) const {
    if (s < shared_slots) {
      float* b = sh.box[s][side];
      lo = {handover_load(&b[0]), handover_load(&b[1]), handover_load(&b[2]), 0};
      hi = {handover_load(&b[3]), handover_load(&b[4]), handover_load(&b[5]), 0};
    } else {
      lo = span_lo[2 * size_t(s) + side];
      hi = span_hi[2 * size_t(s) + side];
    }
  }

  // From slot s, whose box on side `side` is in place (put there in phase 0): arrive; the
  // first arrival at a slot stops, the second merges both sides, keeps the merge on side 0
  // for the write-back, and puts it on its side of the parent before arriving there.
  CDB_HD void climb(uint32_t s, uint32_t side, Shared& sh) const {
    for (;;) {
      uint32_t* word = s < shared_slots ? &sh.arrived[s / 32] : &span_arrived[s / 32];
      const uint32_t bit = 1u << (s % 32);
      if ((atomic_xor_acq_rel_block(word, bit) & bit) == 0) return;  // the sibling finishes s
      vec4f lo, hi, olo, ohi;
      get(s, 0, lo, hi, sh);
      get(s, 1, olo, ohi, sh);
      lo = {min_of(lo.x, olo.x), min_of(lo.y, olo.y), min_of(lo.z, olo.z), 0};
      hi = {max_of(hi.x, ohi.x), max_of(hi.y, ohi.y), max_of(hi.z, ohi.z), 0};
      put(s, 0, lo, hi, sh);
      const uint32_t up = s < shared_slots ? sh.parent[s] : span_parent[s];
      if (up == kNoNode) return;
      s = ref_index(up);
      side = is_leaf(up) ? 1u : 0u;
      put(s, side, lo, hi, sh);
    }
  }
};

}  // namespace cdb
