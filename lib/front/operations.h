#pragma once
// The front operations of Fig. 4 as functors: (1) generate, (2) preserve, (3) update
// (sprout/prune, Alg. 1 lines 12-47) and the opt marks of (4) balance. Leaf i's box is
// tested against node boxes; pairs go to a PairSink in mesh face indices. The same functors
// serve self fronts (leaf i of a tree against that tree) and cross fronts (leaf i of T_D
// against T_R, docs/design.md "Deformable and rigid objects"); FrontView says which.
#include <cstdint>
#include <type_traits>

#include "cdbench/bvh/bvh_view.h"
#include "cdbench/bvh/traverse.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/front/front.h"
#include "cdbench/front/ordering.h"
#include "cdbench/front/warp_traversal.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

// What the front kernels read of the tree beyond BvhView: parent links for pruning.
struct FrontTree {
  BvhView bvh;
  const uint32_t* leaf_parent;
  const uint32_t* node_parent;

  CDB_HD_INLINE bool overlaps_node(const vec4f& lo, const vec4f& hi, uint32_t ref) const {
    const uint32_t k = ref_index(ref);
    const NodeBox b = is_leaf(ref) ? bvh.leaf_box[k] : bvh.node_box[k];
    return overlaps(lo, hi, b.lo, b.hi);
  }
  CDB_HD_INLINE uint32_t parent(uint32_t ref) const {
    return is_leaf(ref) ? leaf_parent[ref_index(ref)] : node_parent[ref];
  }
};

// Both sides of a front (i, j): query leaf i (its box and face) and the tree j lies in.
// A self front's query leaves are the tree's own: leaf i starts at its escape index and
// its front partitions the leaves (i, N-1], so each pair is met once. A cross front's query
// leaves are another tree's: leaf i starts at the root and its front partitions all N
// leaves; the two trees hold disjoint faces, so each pair is met once too.
struct FrontView {
  FrontTree tree;
  const NodeBox* query;  // the query leaves' boxes
  bool cross;

  // Where the query leaf with corner `lo` starts: a self front's leaf is the tree's own, and
  // its escape index rides in its box (node_ref.h).
  CDB_HD_INLINE uint32_t start(const vec4f& lo) const { return cross ? tree.bvh.root() : lane_link(lo.w); }
};

// A traversal task whose query carries this bit records no stop nodes: a front node kept as
// it is (restructure's valid nodes) is traversed for its pairs only. Leaf indices stay below
// kMaxLeaves (node_ref.h), so the top bit is free.
inline constexpr uint32_t kKeptQuery = kLeafBit;

// The traversal (bvh/traverse.h) of the nodes from `node` up to (not including) `end` for
// query leaf i: leaves that overlap are pairs, and its stop nodes are pushed to the front
// (a FrontSink, or a PatchSink) when kRecord.
template <bool kRecord, class Sink = const FrontSink&>
CDB_HD_INLINE void traverse_range(const FrontView& v, uint32_t i, const vec4f& lo, const vec4f& hi,
                                  uint32_t node, uint32_t end, const PairSink& pairs, Sink&& front) {
  const uint32_t prim = lane_link(hi.w);  // the query leaf's primitive rides in its box (node_ref.h)
  traverse(v.tree.bvh, lo, hi, node, end, [&](uint32_t other) { pairs.emit(prim, other); },
           [&](uint32_t stop) { if constexpr (kRecord) front.push(i, stop, 1); });
}

// (1) Generate: the leaf algorithm from leaf i's start (escape index, or the root of a
// cross front), recording its stop nodes. On the GPU the traversals are shared out within
// each warp (front/warp_traversal.h) when share_in_warp: a generate is one whole traversal
// per leaf, the longest traversals of any front operation, and alone the warps ran at 8 to
// 10 of 32 lanes (Nsight Compute, docs/experiments.md).
// 2^spread_shift threads run each leaf (warp_traversal.h, "Spread launches"). The front's
// nodes go to `front`: appended (FrontSink), or each at its sorted place (PlacedFrontSink,
// front/ordering.h).
template <class Sink = FrontSink>
struct GenerateFrontFn {
  using Stage = PairFrontStage;
  FrontView view;
  PairSink pairs;
  Sink front;
  bool share_in_warp = false;
  uint32_t spread_shift = 0;
  CDB_HD PairSink pair_sink(Stage* stage) const { return pairs.staged(stage ? &stage->pairs : nullptr); }
  CDB_HD Sink front_sink(Stage* stage) const { return front.staged(stage ? &stage->front : nullptr); }
  CDB_HD void operator()(uint32_t i, Stage* stage = nullptr) const {
    if (!spread_start(i, spread_shift, i)) return;
    const NodeBox b = view.query[i];
    traverse_range<true>(view, i, b.lo, b.hi, view.start(b.lo), kNoNode, pair_sink(stage), front_sink(stage));
  }
#if defined(__CUDACC__)
  // Every thread of the launch, i past the leaves included (those lanes only help).
  __device__ void warp(uint32_t i, uint32_t n, Stage* stage) const {
    if (!share_in_warp) {
      if (i < n) (*this)(i, stage);
      return;
    }
    TraversalTask t;
    uint32_t leaf = 0;
    if (i < n && spread_start(i, spread_shift, leaf)) {
      const NodeBox b = view.query[leaf];
      const uint32_t start = view.start(b.lo);
      t = {b.lo, b.hi, leaf, start, kNoNode, start != kNoNode};
    }
    const Sink sink = front_sink(stage);
    traverse_in_warp(view.tree.bvh, t, pair_sink(stage), [&](uint32_t q, uint32_t stop) { sink.push(q, stop, 1); });
  }
  __device__ void flush(Stage& s) const {
    pairs.flush(s.pairs);
    front.flush(s.front);
  }
#endif
};

#if defined(__CUDACC__)
// Adds the lanes' two counts (one per front kind) to to[0] and to[1]: once per warp and kind
// where the warp reduction exists (sm_80 and later), else once per lane.
__device__ inline void add_in_warp(unsigned long long* to, const uint32_t (&n)[2]) {
#if __CUDA_ARCH__ < 800
  for (int k = 0; k < 2; ++k)
    if (n[k]) atomicAdd(&to[k], static_cast<unsigned long long>(n[k]));
#else
  const unsigned active = __activemask();
  if (!__any_sync(active, (n[0] | n[1]) != 0)) return;
  for (int k = 0; k < 2; ++k) {
    const uint32_t sum = __reduce_add_sync(active, n[k]);
    if ((threadIdx.x & 31u) == unsigned(__ffs(active) - 1) && sum)
      atomicAdd(&to[k], static_cast<unsigned long long>(sum));
  }
#endif
}
#endif

#if defined(__CUDACC__)
// The pair of kStopSlots slots of two that this block adds to.
__device__ inline unsigned long long* block_slot(unsigned long long* slots) {
  return slots + 2 * (blockIdx.x % kStopSlots);
}
#endif

// Adds a lane's two counts (one per front kind) to kStopSlots slots of two: on the GPU into
// its block's slot (add_in_warp), on the host to the first slot.
CDB_HD_INLINE void add_to_slots(unsigned long long* slots, const uint32_t (&n)[2]) {
#if defined(__CUDA_ARCH__)
  add_in_warp(block_slot(slots), n);
#else
  for (int k = 0; k < 2; ++k)
    if (n[k]) atomic_add_relaxed(&slots[k], static_cast<unsigned long long>(n[k]));
#endif
}

// Front node (i, j)'s own test as preserve makes it: its pair if j is a leaf that overlaps,
// and the traversal left below j (query i | tag). `first`, if given, receives the step.
CDB_HD_INLINE TraversalTask front_node_step(const FrontView& view, const PairSink& pairs, uint32_t i, uint32_t j,
                                            uint32_t tag, NextNode* first = nullptr) {
  const NodeBox b = view.query[i];
  const vec4f &lo = b.lo, &hi = b.hi;
  const uint32_t q = lane_link(hi.w);
  const NextNode step = visit(view.tree.bvh, j, lo, hi, [&](uint32_t other) { pairs.emit(q, other); });
  if (first) *first = step;
  return {lo, hi, i | tag, step.next, step.escape, !step.stop};
}

// A front node (i, j) with query leaf i's box and node j's box loaded; j kFrontDropped for
// none (PreserveTwoNodesFn).
struct GatheredFrontNode {
  NodeBox query, node;
  uint32_t i = 0, j = kFrontDropped;
};

// (2) Preserve: traverse from every stored front node; the front is not rewritten. On the
// GPU the traversals left after the first step are shared out within each warp
// (front/warp_traversal.h). kCountStops (a probe before an update): also count, per kind,
// what an update of the front on this frame's geometry yields at most, into `yield`
// (FrontQueryCounters::yield, kStopSlots slots of two). A front node that overlaps and
// descends yields its descent's stop nodes (UpdateFrontFn sprouts into them), counted by
// kind as the descent meets them. One that does not descend yields at most one node
// (update_front_node_first): a leaf that overlaps keeps itself (external); an internal node
// that misses is kept, climbs to an ancestor or is dropped (internal, if anything); a leaf
// that misses is kept (external) or climbs (internal) or is dropped, so it counts in both
// kinds. Counting the leaves that overlap apart from those that miss keeps the bound of each
// kind near what the update makes: a bound that took every front node for a possible node of
// each kind was 1.5 times the internal front the 522K cloth's update made.
template <bool kCountStops>
struct PreserveFrontFn {
  // A probe's block adds its counts to the slots once (PairCountStage).
  using Stage = std::conditional_t<kCountStops, PairCountStage, PairStage>;
  static constexpr bool kCounts = kCountStops;
  static constexpr bool kWarpTraversal = true;
  static constexpr uint32_t kMinBlocksPerSm = kPreserveMinBlocks;
  FrontView view;
  PairSink pairs;
  const uint32_t* prim;
  const uint32_t* node;
  bool share_in_warp = true;          // on the GPU: each lane alone when false
  unsigned long long* yield = nullptr;  // kCountStops: the count slots
  CDB_HD PairSink pair_sink(Stage* stage) const {
    if constexpr (kCountStops)
      return pairs.staged(stage ? &stage->pairs : nullptr);
    else
      return pairs.staged(stage);
  }
  // Front node e's own test: its pair if it is a leaf that overlaps, and the rest; with
  // kCountStops, what e yields to an update unless it descends is added to `met`.
  CDB_HD TraversalTask first_step(uint32_t e, Stage* stage, uint32_t (&met)[2]) const {
    const uint32_t j = node[e];
    if (j == kFrontDropped) return {};
    NextNode step{};
    const TraversalTask t = front_node_step(view, pair_sink(stage), prim[e], j, 0, kCountStops ? &step : nullptr);
    if constexpr (kCountStops) {
      if (step.stop && !step.leaf_hit) ++met[kInternalFront];
      if (is_leaf(j)) ++met[kExternalFront];
    }
    return t;
  }
  // The same with front node (i, j) and both its boxes gathered already (PreserveTwoNodesFn).
  CDB_HD TraversalTask first_step(const GatheredFrontNode& g, Stage* stage, uint32_t (&met)[2]) const {
    if (g.j == kFrontDropped) return {};
    const NextNode step = next_node_in(g.node, g.j, g.query.lo, g.query.hi);
    if (step.leaf_hit) pair_sink(stage).emit(lane_link(g.query.hi.w), step.prim);
    if constexpr (kCountStops) {
      if (step.stop && !step.leaf_hit) ++met[kInternalFront];
      if (is_leaf(g.j)) ++met[kExternalFront];
    }
    return {g.query.lo, g.query.hi, g.i, step.next, step.escape, !step.stop};
  }
  CDB_HD void operator()(uint32_t e, Stage* stage = nullptr) const {
    uint32_t met[2] = {0, 0};
    rest_alone(first_step(e, stage, met), stage, met);
  }
  // The descent after a first step, by this lane alone; with kCountStops, `met` and the
  // descent's stops go to the slots.
  CDB_HD void rest_alone(const TraversalTask& t, Stage* stage, uint32_t (&met)[2]) const {
    if (t.busy) {
      const PairSink sink = pair_sink(stage);
      const uint32_t q = lane_link(t.hi.w);
      traverse(view.tree.bvh, t.lo, t.hi, t.node, t.end, [&](uint32_t other) { sink.emit(q, other); },
               [&](uint32_t stop) {
                 if constexpr (kCountStops) count_stop(met, stop);
               });
    }
    if constexpr (kCountStops) count_stops(met, stage);
  }
  // Counted per kind without indexing `met` by a value, which would put it in local memory.
  CDB_HD_INLINE static void count_stop(uint32_t (&met)[2], uint32_t stop) {
    const uint32_t external = front_kind(stop) == kExternalFront;
    met[kExternalFront] += external;
    met[kInternalFront] += 1u - external;
  }
  // Into the block's stage where there is one, else straight to the slots.
  CDB_HD_INLINE void count_stops(const uint32_t (&met)[2], [[maybe_unused]] Stage* stage) const {
#if defined(__CUDA_ARCH__)
    if (stage) {
      add_in_warp(stage->met, met);
      return;
    }
#endif
    add_to_slots(yield, met);
  }
#if defined(__CUDACC__)
  // The descents after the first steps, shared out in the warp; `met` holds what this lane's
  // first step counted, added to the slots once with the descents' stops: a second add per
  // warp made the probing preserve markedly dearer (docs/experiments.md).
  __device__ void rest_in_warp(const TraversalTask& t, Stage* stage, uint32_t (&met)[2]) const {
    if constexpr (kCountStops) {
      traverse_in_warp(view.tree.bvh, t, pair_sink(stage), [&](uint32_t, uint32_t stop) { count_stop(met, stop); });
      count_stops(met, stage);
    } else {
      traverse_in_warp(view.tree.bvh, t, pair_sink(stage));
    }
  }
  __device__ void flush(Stage& s) const {
    if constexpr (kCountStops) {
      pairs.flush(s.pairs);
      if (threadIdx.x == 0) add_stage_to_slots(s.met);
    } else {
      pairs.flush(s);
    }
  }
  // One thread of the block: what its warps counted, to the block's slot.
  __device__ void add_stage_to_slots(const unsigned long long (&met)[2]) const {
    unsigned long long* slot = block_slot(yield);
    for (int k = 0; k < 2; ++k)
      if (met[k]) atomicAdd(&slot[k], met[k]);
  }
#endif
};

// (3) Update: an overlapping front node sprouts (its subtree's stop nodes replace it); a
// missing one prunes: it climbs while it is a left child whose parent also misses, and the
// node it ends on is kept only if it is a left child or its parent overlaps. A right child
// under a missing parent is dropped: the leftmost front node of that parent's subtree climbs
// to it, so the front stays a partition of (i, N-1]. In a self front the climb never reaches
// a node holding leaf i: such a node contains leaf i's box and so always overlaps. A cross
// front partitions all leaves: its climb may end at the root, which is then kept (father
// kNoNode), and the leftmost-node argument is the same.
// Everything but a sprout's traversal, which is returned as a task (busy when front node j
// sprouts), so that it can run alone or shared out in the warp.
// `front` is a FrontSink, or a PatchSink for an update in place.
template <class Sink>
CDB_HD_INLINE TraversalTask update_front_node_first(const FrontView& view, const PairSink& pairs, Sink& front,
                                                    uint32_t i, uint32_t j) {
  const FrontTree& tree = view.tree;
  const NodeBox b = view.query[i];
  const vec4f &lo = b.lo, &hi = b.hi;
  const NextNode step = next_node(tree.bvh, j, lo, hi);
  if (step.leaf_hit) {
    pairs.emit(lane_link(hi.w), step.prim);
    front.push(i, j, 1);
    return {};
  }
  if (!step.stop) return {lo, hi, i, step.next, step.escape, true};
  // Each father's left link comes with its box (node_ref.h).
  uint32_t child = j, father = tree.parent(j);
  for (;;) {
    if (father == kNoNode) {
      front.push(i, child, 0);
      return {};
    }
    const NodeBox f = tree.bvh.node_box[father];
    const bool left_child = lane_link(f.lo.w) == child, hit = overlaps(lo, hi, f.lo, f.hi);
    if (!left_child || hit) {
      if (left_child || hit) front.push(i, child, 0);
      return {};
    }
    child = father;
    father = tree.node_parent[father];
  }
}

// The front's nodes go to `front`: appended (FrontSink), or each at its sorted place
// (PlacedFrontSink, front/ordering.h).
template <class Sink = FrontSink>
struct UpdateFrontFn {
  using Stage = PairFrontStage;
  static constexpr bool kWarpTraversal = true;
  FrontView view;
  PairSink pairs;
  Sink front;
  const uint32_t* prim;
  const uint32_t* node;
  bool share_in_warp = true;  // on the GPU: each lane sprouts alone when false
  CDB_HD PairSink pair_sink(Stage* stage) const { return pairs.staged(stage ? &stage->pairs : nullptr); }
  CDB_HD Sink front_sink(Stage* stage) const { return front.staged(stage ? &stage->front : nullptr); }
  CDB_HD TraversalTask first_step(uint32_t e, Stage* stage) const {
    const uint32_t j = node[e];
    if (j == kFrontDropped) return {};
    const Sink sink = front_sink(stage);
    return update_front_node_first(view, pair_sink(stage), sink, prim[e], j);
  }
  CDB_HD void operator()(uint32_t e, Stage* stage = nullptr) const {
    const TraversalTask t = first_step(e, stage);
    if (t.busy) traverse_range<true>(view, t.query, t.lo, t.hi, t.node, t.end, pair_sink(stage), front_sink(stage));
  }
#if defined(__CUDACC__)
  __device__ void rest_in_warp(const TraversalTask& t, Stage* stage) const {
    const Sink sink = front_sink(stage);
    traverse_in_warp(view.tree.bvh, t, pair_sink(stage), [&](uint32_t i, uint32_t stop) { sink.push(i, stop, 1); });
  }
  __device__ void flush(Stage& s) const {
    pairs.flush(s.pairs);
    front.flush(s.front);
  }
#endif
};

// (3) Update in place: the sprouts and prunes of UpdateFrontFn, written into the current
// front instead of a new one, so that an update writes what changed, not the whole front
// (docs/front-maintenance.md "Updates in place"). Front node e's first output of its own
// kind takes its place (not written when it is e's node: a leaf kept, a node whose father
// overlaps); e is dropped where it lies (kFrontDropped) when it has none (a sprout, a right
// child under a missing father, a leaf that climbs to an internal node), and every other
// output is appended (to the front's end, or to a tail that is sorted there after:
// FrontQuery::patch). So the front holds the nodes UpdateFrontFn would produce, in its old
// order but for holes and an appended tail. Where the front's count log is kept (pipeline
// c's inspection reads it), every change moves its counts. Appends past the capacity are
// counted, not stored; the front is then incomplete and must be generated again.
struct PatchSink {
  // Plain members only (no copy of a sink, no array indexed by kind), so that the compiler
  // keeps the sink in registers: a copy of FrontSink here went to local memory and made the
  // kernel DRAM-bound (docs/experiments.md).
  const FrontSink& append;
  uint32_t* count_internal;  // the current front's count logs per kind, or null: not kept
  uint32_t* count_external;
  uint32_t* node;  // the current front's nodes of e's kind
  uint32_t e, j;
  bool placed = false;
  CDB_HD_INLINE void push(uint32_t i, uint32_t ref, uint8_t m) {
    recount(ref, 1u);
    if (!placed && is_leaf(ref) == is_leaf(j)) {
      placed = true;
      if (ref == j) {
        recount(ref, ~0u);
        return;
      }
      node[e] = ref;
      recount(j, ~0u);
      return;
    }
    append.push(i, ref, m);
  }
  // Adds `delta` (~0u: -1) to the current front's count of `ref`, if kept.
  CDB_HD_INLINE void recount(uint32_t ref, uint32_t delta) const {
    if (uint32_t* log = is_leaf(ref) ? count_external : count_internal) atomic_add_relaxed(&log[ref_index(ref)], delta);
  }
};

struct PatchFrontFn {
  // Only pairs are staged per block: an update in place appends few nodes, and a front stage
  // cost its flush and barrier in every block (docs/experiments.md).
  using Stage = PairStage;
  static constexpr bool kWarpTraversal = true;
  FrontView view;
  PairSink pairs;
  FrontSink append;  // both kinds: past the current fronts' ends, or tails sorted there after
  const uint32_t* prim;
  uint32_t* node;
  unsigned long long* dropped;  // FrontQueryCounters::dropped: front nodes dropped in place
  bool share_in_warp = true;
  uint32_t* count_internal = nullptr;  // PatchSink's count logs
  uint32_t* count_external = nullptr;
  CDB_HD PairSink pair_sink(Stage* stage) const { return pairs.staged(stage); }
  CDB_HD TraversalTask first_step(uint32_t e, Stage* stage) const {
    const uint32_t j = node[e];
    if (j == kFrontDropped) return {};
    PatchSink sink{append, count_internal, count_external, node, e, j};
    const TraversalTask t = update_front_node_first(view, pair_sink(stage), sink, prim[e], j);
    if (!sink.placed) {
      node[e] = kFrontDropped;
      sink.recount(j, ~0u);
    }
    const uint32_t drop[2] = {!sink.placed && !is_leaf(j) ? 1u : 0u, !sink.placed && is_leaf(j) ? 1u : 0u};
    add_to_slots(dropped, drop);
    return t;
  }
  // The sink of a sprout's stop nodes: every one appended.
  CDB_HD PatchSink appending() const { return {append, count_internal, count_external, node, 0, kFrontDropped, true}; }
  CDB_HD void operator()(uint32_t e, Stage* stage = nullptr) const {
    const TraversalTask t = first_step(e, stage);
    if (t.busy) traverse_range<true>(view, t.query, t.lo, t.hi, t.node, t.end, pair_sink(stage), appending());
  }
#if defined(__CUDACC__)
  __device__ void rest_in_warp(const TraversalTask& t, Stage* stage) const {
    PatchSink sink = appending();
    traverse_in_warp(view.tree.bvh, t, pair_sink(stage), [&](uint32_t i, uint32_t stop) { sink.push(i, stop, 1); });
  }
  __device__ void flush(Stage& s) const { pairs.flush(s); }
#endif
};

// Both kinds of front (internal, external) in one launch: index e < n0 is the first's, the
// rest the second's. Each pass is as long as its slowest traversal, so one launch lets the
// two tails overlap instead of adding up. Both passes append to the same sinks, so the
// first's flush writes out the stage of both.
// 2^spread_shift threads run each front node (warp_traversal.h, "Spread launches"): the
// launch has that many times as many threads as nodes.
template <class F>
struct BothFrontsFn {
  using Stage = typename F::Stage;
  static constexpr uint32_t kMinBlocksPerSm = min_blocks_per_sm<F>();
  F first, second;
  uint32_t n0;
  uint32_t spread_shift = 0;
  CDB_HD void operator()(uint32_t e, Stage* stage = nullptr) const {
    if (!spread_start(e, spread_shift, e)) return;
    if (e < n0)
      first(e, stage);
    else
      second(e - n0, stage);
  }
#if defined(__CUDACC__)
  __device__ void flush(Stage& s) const { first.flush(s); }
  // Every thread of the launch, e past the fronts included (those lanes only help): each
  // starting lane's first step, then the rest shared out in the warp. Both passes share
  // the tree and the sinks.
  __device__ void warp(uint32_t e, uint32_t n, Stage* stage) const
    requires F::kWarpTraversal
  {
    if (!first.share_in_warp) {
      if (e < n) (*this)(e, stage);
      return;
    }
    TraversalTask t;
    uint32_t node = 0;
    const bool starts = e < n && spread_start(e, spread_shift, node);
    // A probing preserve counts its first steps with the descents (PreserveFrontFn).
    if constexpr (requires(uint32_t (&m)[2]) { first.first_step(node, stage, m); }) {
      uint32_t met[2] = {0, 0};
      if (starts) t = node < n0 ? first.first_step(node, stage, met) : second.first_step(node - n0, stage, met);
      first.rest_in_warp(t, stage, met);
    } else {
      if (starts) t = node < n0 ? first.first_step(node, stage) : second.first_step(node - n0, stage);
      first.rest_in_warp(t, stage);
    }
  }
#endif
};

// Preserve over both kinds of front (as BothFrontsFn, no spread) with two front nodes a
// thread (--preserve-two-nodes): thread l of block b (blocks of kStagedThreads) takes front
// nodes 2 * kStagedThreads * b + l and kStagedThreads past it, both loads coalesced. It
// gathers both nodes' boxes before it tests either, so that it has two sets of gathered
// loads in flight where a thread of one node has one: the preserve of the large cloths
// waits on those loads (docs/results.md). The launch has about half as many threads.
// It runs without a register bound: it takes 48 registers, 40 warps an SM; under a bound of 6
// blocks (40 registers, some spilled) it lost what two nodes gained (H200, docs/experiments.md).
template <class F>
struct PreserveTwoNodesFn {
  using Stage = typename F::Stage;
  F first, second;
  uint32_t n0;
  uint32_t n;  // front nodes of both kinds

  // The threads a launch over n front nodes takes.
  static constexpr uint64_t threads_for(uint64_t nodes) {
    return (nodes + 2 * kStagedThreads - 1) / (2 * kStagedThreads) * kStagedThreads;
  }
  CDB_HD_INLINE static uint32_t first_node(uint32_t e) { return e + (e & ~(kStagedThreads - 1u)); }

  // Front node e's indices and boxes; without branches, so that the loads of both of a
  // thread's nodes are in flight together (a node past the fronts or dropped reads entry 0).
  CDB_HD_INLINE GatheredFrontNode gather(uint32_t e) const {
    const bool in = e < n, in_first = e < n0;
    const uint32_t k = !in ? 0u : in_first ? e : e - n0;
    const uint32_t* prim = in_first ? first.prim : second.prim;
    const uint32_t* node = in_first ? first.node : second.node;
    GatheredFrontNode g;
    g.j = in ? node[k] : kFrontDropped;
    g.i = in ? prim[k] : 0u;
    const BvhView& bvh = first.view.tree.bvh;
    const bool dropped = g.j == kFrontDropped;
    g.query = first.view.query[dropped ? 0u : g.i];
    g.node = (is_leaf(g.j) ? bvh.leaf_box : bvh.node_box)[dropped ? 0u : ref_index(g.j)];
    return g;
  }

  // Both nodes' gathers, then both first steps, then each descent. warp() repeats the first
  // lines: through a helper that filled arrays of both tasks, ptxas allocated the kernels
  // anew (46 registers to 44), a change not measured on a GPU.
  CDB_HD void operator()(uint32_t e, Stage* stage = nullptr) const {
    const uint32_t e0 = first_node(e);
    const GatheredFrontNode g0 = gather(e0), g1 = gather(e0 + kStagedThreads);
    uint32_t met0[2] = {0, 0}, met1[2] = {0, 0};
    const TraversalTask t0 = first.first_step(g0, stage, met0);
    const TraversalTask t1 = first.first_step(g1, stage, met1);
    first.rest_alone(t0, stage, met0);
    first.rest_alone(resumed(t1), stage, met1);
  }
#if defined(__CUDACC__)
  __device__ void flush(Stage& s) const { first.flush(s); }
  // Every thread of the launch (those past the fronts only help): both first steps, then
  // the rest of each shared out in the warp, one after the other.
  __device__ void warp(uint32_t e, uint32_t threads, Stage* stage) const
    requires F::kWarpTraversal
  {
    if (!first.share_in_warp) {
      if (e < threads) (*this)(e, stage);
      return;
    }
    const uint32_t e0 = first_node(e);
    const GatheredFrontNode g0 = gather(e0), g1 = gather(e0 + kStagedThreads);
    uint32_t met0[2] = {0, 0}, met1[2] = {0, 0};
    const TraversalTask t0 = first.first_step(g0, stage, met0);
    const TraversalTask t1 = first.first_step(g1, stage, met1);
    first.rest_in_warp(t0, stage, met0);
    first.rest_in_warp(resumed(t1), stage, met1);
  }
#endif

 private:
  // The second node's descent, held as its query leaf and range while the first's runs
  // and its box loaded again after: a whole task held across the first descent cost the
  // loop ten registers.
  CDB_HD_INLINE TraversalTask resumed(const TraversalTask& t) const {
    if (!t.busy) return {};
    const NodeBox q = first.view.query[t.query];
    return {q.lo, q.hi, t.query, t.node, t.end, true};
  }
};

// (4) Balance: the opt mark each front node will take in the coming update (1 = sprout),
// for the radix sort, which orders by node and mark.
struct MarkFrontFn {
  FrontView view;
  const uint32_t* prim;
  const uint32_t* node;
  uint8_t* mark;
  CDB_HD void operator()(uint32_t e) const {
    const uint32_t i = prim[e], j = node[e];
    const NodeBox b = view.query[i];
    mark[e] = view.tree.overlaps_node(b.lo, b.hi, j) ? 1 : 0;
  }
};

// (4) Balance with the histogram sort, in one pass: the current front has not changed
// since the histogram sort that ordered it, so that sort's offset log still gives each BVH
// node's segment; each front node takes its opt mark and goes straight to its side of the
// segment (sprouts from the back, as ScatterFrontFn places them). No count, no scan, no
// mark array.
struct MarkScatterFrontFn {
  FrontView view;
  const uint32_t* prim;
  const uint32_t* node;
  SegmentScatter to;
  CDB_HD void operator()(uint32_t e) const {
    const uint32_t i = prim[e], j = node[e];
    const NodeBox b = view.query[i];
    to.place(i, j, view.tree.overlaps_node(b.lo, b.hi, j));
  }
};

}  // namespace cdb
