#pragma once
// The front traversals (preserve's, and the sprouts of update) shared out within a warp. A
// front node that starts to overlap descends its subtree alone, one dependent load a step,
// and the warp waits for its longest lane: the preserve and update kernels ran with about
// half their lanes active (Nsight Compute, docs/experiments.md).
// Here a lane with nothing left takes over part of a busy lane's traversal, and the warp's
// steps approach its lanes' total over 32 instead of its longest lane's.
//
// A stackless traversal from `node` up to (not including) `end` splits without a stack: at
// an internal node that overlaps, the traversal visits the node's subtree, [node, escape),
// then goes on with [escape, end), which is itself a stackless traversal from escape to end.
// A lane that steps onto such a node with escape != end can give [escape, end) away and keep
// the subtree (its end becomes escape). After each step of the warp, the k-th idle lane
// takes the k-th offer (ballots, then one shuffle of the task per value). The pieces
// partition the lane's traversal: the same pairs, and the same stop nodes for on_stop.
#include <cstdint>
#include <type_traits>

#include "cdbench/bvh/bvh_view.h"
#include "cdbench/bvh/traverse.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

// What is left of a traversal: from `node` up to (not including) `end`, for query leaf
// `query` whose box is lo, hi (its primitive rides in hi.w, node_ref.h). Idle when nothing
// is left.
struct TraversalTask {
  vec4f lo, hi;
  uint32_t query = 0, node = kNoNode, end = kNoNode;
  bool busy = false;
};

// Spread launches: a launch of fewer traversals than the GPU holds threads (a generate of a
// small mesh: a few thousand leaves, each one long traversal) leaves most of the GPU idle
// while each warp works through its own 32. Launched with 2^shift threads per traversal,
// thread e << shift starts traversal e and the others start idle and take pieces of their
// warp's traversals as above. spread_shift_for picks the largest spread up to 32 that keeps
// the launch within `waves` times the resident threads (none past them; kSpreadWaves* in
// exec/tuning.h). A shift, not a factor: a division by a value known only at run time costs
// every thread of the launch, the preserve's millions included.
inline constexpr uint32_t kMaxSpreadShift = 5;  // 32 threads, a warp

CDB_HD_INLINE uint32_t spread_shift_for(uint64_t traversals, uint64_t resident_threads, uint64_t waves) {
  uint32_t shift = 0;
  while (shift < kMaxSpreadShift && (traversals << (shift + 1)) <= waves * resident_threads) ++shift;
  return shift;
}

// Thread e of a spread launch: true, with its traversal's index, for the thread that starts
// one.
CDB_HD_INLINE bool spread_start(uint32_t e, uint32_t shift, uint32_t& index) {
  if (e & ((1u << shift) - 1u)) return false;
  index = e >> shift;
  return true;
}

// A traversal that records no stop nodes (preserve).
struct NoFrontStop {
  CDB_HD_INLINE void operator()(uint32_t, uint32_t) const {}
};

#if defined(__CUDACC__)
// Every lane of the warp calls this together, idle ones included. on_stop(query, node) gets
// each stop node of the traversal, as traverse's on_stop does (update records them).
template <class OnStop = NoFrontStop>
__device__ void traverse_in_warp(const BvhView& bvh, TraversalTask t, const PairSink& sink, OnStop on_stop = {}) {
  constexpr unsigned kAll = 0xffffffffu;
  const unsigned lane = threadIdx.x & 31u, below = (1u << lane) - 1u;
  for (;;) {
    uint32_t offer = kNoNode;  // [offer, t.end): the traversal's rest after this node's subtree
    if (t.busy) {
      const uint32_t q = lane_link(t.hi.w);
      const uint32_t query = t.query;
      const NextNode step = visit(bvh, t.node, t.lo, t.hi, [&](uint32_t other) { sink.emit(q, other); },
                                  [&](uint32_t stop) { on_stop(query, stop); });
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
    // Only a traversal that records its stops needs to know whose they are.
    uint32_t query = 0;
    if constexpr (!std::is_same_v<OnStop, NoFrontStop>) query = __shfl_sync(kAll, t.query, src);
    if (takes) t = {{lx, ly, lz, 0.0f}, {hx, hy, hz, hw}, query, node, end, true};
    if (gives) t.end = offer;
  }
}
#endif

}  // namespace cdb
