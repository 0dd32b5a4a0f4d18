#pragma once
// The front traversals (preserve, and update's sprouts) shared out within a warp. A front
// node that starts to overlap descends its subtree alone, one dependent load a step, and the
// warp waits for its longest lane: the preserve kernels ran at 12 to 22 of 32 lanes active,
// update's at 13 to 18 (results/gpu-targets/ncu-*.md). Here a lane with nothing left takes
// over part of a busy lane's traversal, and the warp's steps approach its lanes' total over
// 32 instead of its longest lane's.
//
// A stackless traversal from `node` up to (not including) `end` splits without a stack: at
// an internal node that overlaps, the traversal visits the node's subtree, [node, escape),
// then goes on with [escape, end), which is itself a stackless traversal from escape to end.
// A lane that steps onto such a node with escape != end can give [escape, end) away and keep
// the subtree (its end becomes escape). After each step of the warp, the k-th idle lane
// takes the k-th offer (ballots, then one shuffle of the task per value). The pieces
// partition the lane's traversal: the same pairs, and with kRecord the same stop nodes.
#include <cstdint>

#include "bvh/bvh_view.h"
#include "bvh/next_node.h"
#include "core/pair_sink.h"
#include "front/front.h"

namespace cdb {

// What is left of a traversal: from `node` up to (not including) `end`, for query leaf
// `query` whose box is lo, hi (its primitive rides in hi.w, node_ref.h). Idle when nothing
// is left.
struct TraversalTask {
  vec4f lo, hi;
  uint32_t query = 0, node = kNoNode, end = kNoNode;
  bool busy = false;
};

#if defined(__CUDACC__)
// Every lane of the warp calls this together, idle ones included. With kRecord the stop
// nodes go to `front` as sprouts (update), as traverse_range<true> records them.
template <bool kRecord>
__device__ void traverse_in_warp(const BvhView& bvh, TraversalTask t, const PairSink& pairs,
                                 const FrontSink& front) {
  constexpr unsigned kAll = 0xffffffffu;
  const unsigned lane = threadIdx.x & 31u, below = (1u << lane) - 1u;
  for (;;) {
    uint32_t offer = kNoNode;  // [offer, t.end): the traversal's rest after this node's subtree
    if (t.busy) {
      const NextNode step = next_node(bvh, t.node, t.lo, t.hi);
      if (step.leaf_hit) pairs.emit(lane_link(t.hi.w), step.prim);
      if (kRecord && step.stop) front.push(t.query, t.node, 1);
      if (!step.stop && step.escape != t.end) offer = step.escape;
      t.node = step.next;
      t.busy = t.node != t.end;
    }
    const unsigned idle = __ballot_sync(kAll, !t.busy);
    if (idle == kAll) return;
    const unsigned offers = __ballot_sync(kAll, offer != kNoNode);
    const unsigned moves = min(__popc(idle), __popc(offers));
    if (moves == 0) continue;
    // An offering lane is busy (it went on into the subtree), so the two ranks do not mix.
    const unsigned rank = __popc((t.busy ? offers : idle) & below);
    const bool takes = !t.busy && rank < moves, gives = offer != kNoNode && rank < moves;
    unsigned from = offers;
    for (unsigned k = 0; takes && k < rank; ++k) from &= from - 1u;
    const unsigned src = takes ? unsigned(__ffs(from) - 1) : lane;
    const float lx = __shfl_sync(kAll, t.lo.x, src), ly = __shfl_sync(kAll, t.lo.y, src),
                lz = __shfl_sync(kAll, t.lo.z, src), hx = __shfl_sync(kAll, t.hi.x, src),
                hy = __shfl_sync(kAll, t.hi.y, src), hz = __shfl_sync(kAll, t.hi.z, src),
                hw = __shfl_sync(kAll, t.hi.w, src);
    const uint32_t node = __shfl_sync(kAll, offer, src), end = __shfl_sync(kAll, t.end, src);
    const uint32_t query = kRecord ? __shfl_sync(kAll, t.query, src) : 0u;
    if (takes) t = {{lx, ly, lz, 0.0f}, {hx, hy, hz, hw}, query, node, end, true};
    if (gives) t.end = offer;
  }
}
#endif

}  // namespace cdb
