#pragma once
// Preserve's traversals shared out within a warp. A front node that starts to overlap
// descends its subtree alone, one dependent load a step, and the warp waits for its longest
// lane: the preserve kernels ran at 12 to 22 of 32 lanes active (results/2026-11-25-h100/ncu-*.md).
// Here a lane with nothing left takes over part of a busy lane's traversal, and the warp's
// steps approach its lanes' total over 32 instead of its longest lane's.
//
// A stackless traversal from `node` up to (not including) `end` splits without a stack: at
// an internal node that overlaps, the traversal visits the node's subtree, [node, escape),
// then goes on with [escape, end), which is itself a stackless traversal from escape to end.
// A lane that steps onto such a node with escape != end can give [escape, end) away and keep
// the subtree (its end becomes escape). After each step of the warp, the k-th idle lane
// takes the k-th offer (ballots, then one shuffle of the task per value). The pairs are
// those of one lane's traversal: the pieces partition it.
#include <cstdint>

#include "bvh/bvh_view.h"
#include "bvh/traverse.h"
#include "core/pair_sink.h"

namespace cdb {

// What is left of a traversal: from `node` up to (not including) `end`, for the query leaf
// whose box is lo, hi (its primitive rides in hi.w, node_ref.h). Idle when nothing is left.
struct PreserveTask {
  vec4f lo, hi;
  uint32_t node = kNoNode, end = kNoNode;
  bool busy = false;
};

#if defined(__CUDACC__)
// Every lane of the warp calls this together, idle ones included.
__device__ inline void traverse_in_warp(const BvhView& bvh, PreserveTask t, const PairSink& sink) {
  constexpr unsigned kAll = 0xffffffffu;
  const unsigned lane = threadIdx.x & 31u, below = (1u << lane) - 1u;
  for (;;) {
    uint32_t offer = kNoNode;  // [offer, t.end): the traversal's rest after this node's subtree
    if (t.busy) {
      const uint32_t q = lane_link(t.hi.w);
      const NextNode step = visit(bvh, t.node, t.lo, t.hi, [&](uint32_t other) { sink.emit(q, other); });
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
    if (takes) t = {{lx, ly, lz, 0.0f}, {hx, hy, hz, hw}, node, end, true};
    if (gives) t.end = offer;
  }
}
#endif

}  // namespace cdb
