#pragma once
// The BVTT fronts of one query of a front pipeline: the self fronts of a tree, or the cross
// fronts of T_D's leaves against T_R (docs/design.md "Deformable and rigid objects"). It
// holds both kinds of front, knows its two trees and where its counts lie in the frame's
// counter block (its Query's FrontCounters::query slot), and runs the front operations on
// them; FrontPipeline decides which operation runs when. It counts every change to what its
// launches read (buffers, sizes: revision()), so a recorded frame knows when it is out of
// date. A query the scene does not ask for is inactive: no fronts, no work.
#include <algorithm>
#include <array>
#include <string>
#include <type_traits>
#include <utility>

#include "cdbench/exec/balance.h"
#include "cdbench/exec/tuning.h"
#include "cdbench/front/front.h"
#include "cdbench/front/operations.h"
#include "cdbench/front/ordering.h"
#include "cdbench/front/radix_ordering.h"
#include "cdbench/front/restructure_front.h"
#include "cdbench/pipeline/device_mesh.h"
#include "cdbench/pipeline/front_counters.h"

namespace cdb {

// How a query's fronts are sized, the same for every query of a run (FrontQuery::plan).
struct FrontSizing {
  double per_triangle = 0.0;  // the first capacity, in front nodes per query leaf
  // Updates may run in place (--update-in-place), which needs the tails' counters and more
  // room (FrontQuery::update_bound).
  bool in_place = false;
  // Updates are sized by probes before they run (--update-probe): an adopted front then
  // keeps no spare (FrontQuery::adopt).
  bool probed = false;
  // The produced arrays: the fronts' own, or lent by the current fronts for each build
  // ahead (FrontQuery::lend_produced), as produced arrays or as the current arrays that the
  // work ahead is placed into in order (FrontQuery::produce_placed).
  ProducedArrays produced = ProducedArrays::own;
};

// How a generate, update or restructure produces its fronts.
struct ProduceMode {
  bool histogram = false;      // count the produced nodes per tree node (the histogram sort's counts)
  bool share_in_warp = false;  // the traversals shared out in warps (CUDA)
};

// How a preserve is launched (FrontPipeline::choose_preserve_launch); each choice is part of
// a recorded steady frame's key.
struct PreserveLaunch {
  bool staged = true;         // pairs staged per block, else appended directly (core/append_stage.h)
  bool share_in_warp = true;  // the traversals shared out in warps (CUDA)
  Occupancy occupancy = Occupancy::plain;  // under PreserveFrontFn's register bound or not (exec/tuning.h)
  bool two_nodes = false;  // two front nodes a thread (PreserveTwoNodesFn), where nothing spreads
};

// How an update in place runs (FrontQuery::patch).
struct PatchMode {
  bool share_in_warp = false;  // the sprouts shared out in warps (CUDA)
  // The front's count log (from the sort that produced it) is kept up to date, and
  // offsets() then gives its offset log.
  bool counted = false;
  // The appended nodes go to the raw arrays, counted per tree node, for sort_tails();
  // otherwise they are appended to the front's end as produced.
  bool sort_tail = false;
};

template <class Exec>
class FrontQuery {
 public:
  using Pairs = PairBuffer<Exec, FrontCounters>;

  FrontQuery(Exec& exec, const std::string& name, Query query) : index_(size_t(query)) {
    front_[kInternalFront].bind(exec.memory(), kInternalFront, name);
    front_[kExternalFront].bind(exec.memory(), kExternalFront, name);
  }

  // Query leaves come from `leaves`, front nodes from `tree` (the same tree: self fronts).
  // Both trees must be reserved for their leaf counts already. `active`: the scene asks for
  // the query (else it has no fronts and does no work).
  void plan(Lbvh<Exec>& leaves, Lbvh<Exec>& tree, bool active, const FrontSizing& sizing) {
    leaves_ = &leaves;
    tree_ = &tree;
    active_ = active;
    in_place_ = sizing.in_place;
    probed_ = sizing.probed;
    produced_ = sizing.produced;
    for (auto& f : front_) f.size = 0;
    ++revision_;
    dropped_[0] = dropped_[1] = appended_[0] = appended_[1] = 0;
    if (!active_) return;
    const size_t cap = std::max<size_t>(1024, size_t(sizing.per_triangle * leaves.num_leaves));
    for (int k = 0; k < 2; ++k)
      front_[k].reserve(cap, std::max<size_t>(segments(k), 1), sizing.in_place, sizing.produced);
  }

  bool active() const { return active_; }
  // Changes whenever a buffer or a front size its launches read changes.
  uint64_t revision() const { return revision_; }
  // Entries of kind k, holes left by updates in place included: what a pass over it launches.
  size_t size(int k) const { return front_[k].size; }
  size_t total() const { return front_[0].size + front_[1].size; }
  // Query leaves: the threads of a generate.
  size_t query_leaves() const { return active_ ? leaves_->num_leaves : 0; }
  // Front nodes of kind k (entries but holes), and of both kinds.
  size_t live(int k) const { return front_[k].size - dropped_[k]; }
  size_t live_total() const { return live(kInternalFront) + live(kExternalFront); }
  // Entries changed by updates in place since the front was last produced whole (holes plus
  // appended nodes), as a share of its live nodes: how far its order has decayed.
  double disorder() const {
    const size_t changed = dropped_[0] + dropped_[1] + appended_[0] + appended_[1];
    return changed ? double(changed) / double(std::max<size_t>(live_total(), 1)) : 0.0;
  }
  size_t capacity() const { return front_[0].capacity(); }
  const FrontArrays<Exec>& front(int k) const { return front_[k]; }

  FrontView view() const {
    const Lbvh<Exec>& t = *tree_;
    return {{t.view(), t.leaf_parent.data(), t.node_parent.data()},
            leaves_->leaf_box.data(),
            leaves_ != tree_};
  }

  // Histogram segments of kind k: the traversed tree's internal nodes or leaves.
  size_t segments(int k) const {
    const uint32_t n = tree_->num_leaves;
    return k == kInternalFront ? (n > 1 ? n - 1 : 0) : n;
  }

  int key_bits(int k) const {
    int bits = 1;
    while (bits < 63 && (uint64_t(1) << bits) < 2 * uint64_t(segments(k)) + 2) ++bits;
    return bits;
  }

  // (1) Generate over all query leaves.
  void generate(Exec& exec, Pairs& pairs, const ProduceMode& mode) {
    if (!active_) return;
    const FrontSink sink = produce_sink(exec, pairs, mode.histogram);
    const uint32_t shift = spread_shift(exec, leaves_->num_leaves, mode.share_in_warp, kSpreadWavesGenerate);
    exec.for_each_staged(size_t(leaves_->num_leaves) << shift,
                         GenerateFrontFn<FrontSink>{view(), pairs.sink(), sink, mode.share_in_warp, shift},
                         Balance::uneven);
  }

  // (1) Generate into the current arrays, for fronts that hold no others
  // (ProducedArrays::lent_as_current: a build ahead's, in the arrays the current fronts lend
  // it), in order with the histogram sort (produce_placed).
  void generate_placed(Exec& exec, Pairs& pairs, const ProduceMode& mode) {
    if (!active_) return;
    const uint32_t shift = spread_shift(exec, leaves_->num_leaves, mode.share_in_warp, kSpreadWavesGenerate);
    const size_t threads = size_t(leaves_->num_leaves) << shift;
    produce_placed(exec, pairs, mode, mode.histogram, [&](const auto& sink) {
      using Sink = std::decay_t<decltype(sink)>;
      exec.for_each_staged(threads, GenerateFrontFn<Sink>{view(), pairs.sink(), sink, mode.share_in_warp, shift},
                           Balance::uneven);
    });
  }

  // (3) Update of `source`'s current fronts against `tree` (as update_from), into the
  // current arrays of fronts that hold no others (an update ahead's), in order where
  // `sorted` (produce_placed).
  void update_placed_from(Exec& exec, Pairs& pairs, const ProduceMode& mode, bool sorted, const FrontQuery& source,
                          const FrontView& tree) {
    if (!active_) return;
    const uint32_t shift = spread_shift(exec, source.total(), mode.share_in_warp, kSpreadWavesUpdate);
    produce_placed(exec, pairs, mode, sorted, [&](const auto& sink) {
      using Fn = UpdateFrontFn<std::decay_t<decltype(sink)>>;
      auto pass = [&](const FrontArrays<Exec>& f) {
        return Fn{tree, pairs.sink(), sink, f.prim.data(), f.node.data(), mode.share_in_warp};
      };
      exec.for_each_staged(source.total() << shift,
                           BothFrontsFn<Fn>{pass(source.front_[0]), pass(source.front_[1]),
                                            uint32_t(source.front_[0].size), shift},
                           Balance::uneven);
    });
  }

  // (2) Preserve: the current fronts are traversed, not rewritten. Both kinds in one launch.
  // `probe`: also count what an update of the fronts yields at most, for update_bound.
  void preserve(Exec& exec, Pairs& pairs, const PreserveLaunch& launch, bool probe) {
    if (!active_) return;
    if (probe)
      preserve_with(
          exec, PreserveFrontFn<true>{{}, pairs.sink(), {}, {}, launch.share_in_warp, &counters(pairs)->yield[0][0]},
          launch);
    else
      preserve_with(exec, PreserveFrontFn<false>{{}, pairs.sink(), {}, {}, launch.share_in_warp}, launch);
  }

  // The room an update of the current fronts needs at most, per kind, after a probing
  // preserve of them counted what it yields (`c`, PreserveFrontFn): that yield, or, for an
  // update in place, which appends all but the first node of each kind a front node yields
  // behind the front's entries, the entries and the yield.
  uint64_t update_bound(const FrontCounters& c, int kind) const {
    const uint64_t yield = c.query[index_].yield_of(kind);
    return in_place_ ? size(kind) + yield : yield;
  }

  // After a probing preserve: the front nodes an update of the current fronts makes at most.
  uint64_t update_yield(const FrontCounters& c) const {
    return active_ ? c.query[index_].yield_of(kInternalFront) + c.query[index_].yield_of(kExternalFront) : 0;
  }

  // After a probing preserve: the buffers of a kind that cannot hold update_bound with
  // kProbeSpareDiv to spare grow to hold it so, so that the coming update produces its
  // fronts in one run. The bound holds for the probed frame's geometry; the update runs on
  // a later frame, whose motion the spare covers, and past it the update grows and runs
  // again as before (docs/design.md "Constants and their measurements"). True if a buffer
  // grew.
  bool reserve_for_update(Exec& exec, const FrontCounters& c) {
    if (!active_) return false;
    bool grew = false;
    for (int k = 0; k < 2; ++k) {
      const size_t need = size_t(update_bound(c, k));
      grew = reserve_headroom(exec, front_[k], need + need / kProbeSpareDiv) || grew;
    }
    revision_ += grew;
    return grew;
  }

  // (3) Update: sprout and prune (Alg. 1). Both kinds in one launch.
  void update(Exec& exec, Pairs& pairs, const ProduceMode& mode) { update_from(exec, pairs, mode, *this, view()); }

  // (3) Update of `source`'s current fronts (a query of a tree of as many leaves) against
  // the tree `tree`, produced into this query's produced arrays. An update ahead
  // (pipeline/front_pipeline.h) reads the current self fronts, which only preserve until
  // these replace them, against a copy of T_D's boxes that the frames' refits leave alone.
  void update_from(Exec& exec, Pairs& pairs, const ProduceMode& mode, const FrontQuery& source, const FrontView& tree) {
    if (!active_) return;
    const FrontSink sink = produce_sink(exec, pairs, mode.histogram);
    auto pass = [&](const FrontArrays<Exec>& f) {
      return UpdateFrontFn<FrontSink>{tree, pairs.sink(), sink, f.prim.data(), f.node.data(), mode.share_in_warp};
    };
    const uint32_t shift = spread_shift(exec, source.total(), mode.share_in_warp, kSpreadWavesUpdate);
    exec.for_each_staged(source.total() << shift,
                         BothFrontsFn<UpdateFrontFn<FrontSink>>{pass(source.front_[0]), pass(source.front_[1]),
                                                     uint32_t(source.front_[0].size), shift},
                         Balance::uneven);
  }

  // (3) Update in place (PatchFrontFn): both kinds in one launch. The current front
  // changes as it runs: unlike the other operations it cannot be run again from it. After
  // the read-back, adopt_patch says whether it fit. With `mode.sort_tail`, sort_tails()
  // orders the appended nodes onto the front's end by histogram sort (the appended nodes are
  // the sprouts of the frame's contacts, the ones the next preserves descend from).
  void patch(Exec& exec, Pairs& pairs, const PatchMode& mode) {
    if (!active_) return;
    if (mode.sort_tail && !front_[0].has_tails()) fail("an update in place ran on fronts planned without it");
    FrontSink append{};
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      if (mode.sort_tail) {
        exec.fill(f.tail_counts.data(), f.tail_counts.size(), 0u);
        append.prim[k] = f.raw_prim.data();
        append.node[k] = f.raw_node.data();
        append.count_log[k] = f.tail_count_log();
      } else {
        append.prim[k] = f.prim.data() + f.size;
        append.node[k] = f.node.data() + f.size;
        append.count_log[k] = nullptr;
      }
      append.mark[k] = f.raw_mark.data();
      append.capacity[k] = append_room(k);
    }
    append.count = counters(pairs)->produced;
    unsigned long long* dropped = &counters(pairs)->dropped[0][0];
    auto pass = [&](FrontArrays<Exec>& f) {
      PatchFrontFn fn{view(), pairs.sink(), append, f.prim.data(), f.node.data(), dropped, mode.share_in_warp};
      fn.count_internal = mode.counted ? front_[kInternalFront].count_log() : nullptr;
      fn.count_external = mode.counted ? front_[kExternalFront].count_log() : nullptr;
      return fn;
    };
    const uint32_t shift = spread_shift(exec, total(), mode.share_in_warp, kSpreadWavesUpdate);
    exec.for_each_staged(total() << shift,
                         BothFrontsFn<PatchFrontFn>{pass(front_[0]), pass(front_[1]), uint32_t(front_[0].size), shift},
                         Balance::uneven);
  }

  // After patch with sort_tail: each kind's appended tail (size on the device, in the
  // counters) histogram-sorted onto the front's end.
  void sort_tails(Exec& exec, Pairs& pairs) {
    if (!active_) return;
    FrontArrays<Exec>&fi = front_[kInternalFront], &fe = front_[kExternalFront];
    exec.exclusive_scan_pair(fi.tail_count_log(), fi.tail_offset_log.data(), segments(kInternalFront) + 1,
                             fe.tail_count_log(), fe.tail_offset_log.data(), segments(kExternalFront) + 1,
                             tree_->temp.data(), tree_->temp.size());
    auto scatter = [&](int k) {
      FrontArrays<Exec>& f = front_[k];
      const SegmentScatter to{f.tail_offset_log.data(), f.tail_cursor_front(), f.tail_cursor_back(),
                              f.prim.data() + f.size, f.node.data() + f.size};
      return ScatterFrontFn{&counters(pairs)->produced[k], append_room(k), f.raw_prim.data(), f.raw_node.data(),
                            f.raw_mark.data(), to};
    };
    for_both_kinds(exec, scatter(kInternalFront), append_room(kInternalFront), scatter(kExternalFront),
                   append_room(kExternalFront));
  }

  // After an update in place's read-back (`c`): true if its appends fit, and the front then
  // takes them and the holes it left; false if some were not stored: the front is
  // incomplete and must be generated again. Between frames, the buffers grow to keep room
  // for the next update in place (the probe before it sizes them for its bound too).
  bool adopt_patch(Exec& exec, const FrontCounters& c) {
    if (!active_) return true;
    const FrontQueryCounters& q = c.query[index_];
    for (int k = 0; k < 2; ++k)
      if (q.produced[k] > append_room(k)) return false;
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      f.size += size_t(q.produced[k]);
      appended_[k] += size_t(q.produced[k]);
      dropped_[k] += size_t(q.dropped_of(k));
      reserve_headroom(exec, f, f.size + live(k) / 4, f.size + live(k) / 2);
    }
    ++revision_;
    return true;
  }

  // (5), first half, for self fronts: classify against the tree's node ranges before its
  // candidate subtrees are restructured.
  void classify(Exec& exec, CandidateView cand) {
    if (!active_) return;
    for (auto& f : front_)
      exec.for_each_n(f.size, ClassifyFrontFn{tree_->node_first.data(), tree_->node_last.data(), cand,
                                              f.prim.data(), f.node.data()});
  }

  // (5), second half: the front pass over the classified self fronts, both kinds in one
  // launch.
  void restructure(Exec& exec, Pairs& pairs, const ProduceMode& mode, CandidateView cand) {
    if (!active_) return;
    const FrontSink sink = produce_sink(exec, pairs, mode.histogram);
    auto pass = [&](const FrontArrays<Exec>& f) {
      return RestructureFrontFn{view(), pairs.sink(), sink, cand, f.prim.data(), f.node.data(), mode.share_in_warp};
    };
    const uint32_t shift = spread_shift(exec, total(), mode.share_in_warp, kSpreadWavesUpdate);
    exec.for_each_n(total() << shift,
                    BothFrontsFn<RestructureFrontFn>{pass(front_[0]), pass(front_[1]), uint32_t(front_[0].size), shift},
                    Balance::uneven);
  }

  // Histogram sort of the produced fronts (sizes on the device in the counters): both
  // kinds' count logs scanned together, then one scatter launch for both, into the current
  // arrays where all of the frame's appends fit (`fit`, FrontArrays).
  void order(Exec& exec, Pairs& pairs, const FrameFit& fit) {
    if (!active_) return;
    offsets(exec);
    auto scatter = [&](int k) {
      FrontArrays<Exec>& f = front_[k];
      return ScatterFrontFn{&counters(pairs)->produced[k], f.capacity(), f.raw_prim.data(), f.raw_node.data(),
                            f.raw_mark.data(), segment_scatter(f, f.prim, f.node), fit};
    };
    for_both_kinds(exec, scatter(kInternalFront), front_[kInternalFront].capacity(), scatter(kExternalFront),
                   front_[kExternalFront].capacity());
  }

  // Adds the counts of what this frame's operation appends, against the room it had, to
  // `fit`: the fronts it produced, or the tails an update in place (`patching`) appended.
  void add_to_fit(FrameFit& fit, Pairs& pairs, bool patching) {
    if (!active_) return;
    for (int k = 0; k < 2; ++k) fit.add(&counters(pairs)->produced[k], patching ? append_room(k) : front_[k].capacity());
  }
  // The same on the host, from the frame's read-back: whether this query's appends fit.
  bool fits(const FrontCounters& c, bool patching) const {
    if (!active_) return true;
    for (int k = 0; k < 2; ++k)
      if (c.query[index_].produced[k] > (patching ? append_room(k) : front_[k].capacity())) return false;
    return true;
  }

  // The produced fronts' offset logs alone (the count logs' scans), for fronts kept in the
  // order they were produced: balance scatters by them and the inspection reads them.
  void offsets(Exec& exec) {
    if (!active_) return;
    FrontArrays<Exec>&fi = front_[kInternalFront], &fe = front_[kExternalFront];
    exec.exclusive_scan_pair(fi.count_log(), fi.offset_log.data(), segments(kInternalFront) + 1, fe.count_log(),
                             fe.offset_log.data(), segments(kExternalFront) + 1, tree_->temp.data(),
                             tree_->temp.size());
  }

  // Radix sort of the produced fronts, with their sizes read back (`c`), into the current
  // arrays; nothing where some append of the frame did not fit (`frame_fits`): the frame
  // runs again from the current fronts.
  void radix_order(Exec& exec, RadixScratch<Exec>& radix, const FrontCounters& c, bool frame_fits) {
    if (!active_ || !frame_fits) return;
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      radix_order_front(exec, radix, size_t(c.query[index_].produced[k]), key_bits(k), f.raw_prim.data(),
                        f.raw_node.data(), f.raw_mark.data(), f.prim.data(), f.node.data());
    }
  }

  // (4) Balance: mark each current front node with the branch it will take, then reorder
  // the current front by node key and mark, into the raw arrays, which then swap with the
  // current ones (the update after produces into the old current arrays). The front's
  // content is unchanged. With the histogram sort, the front keeps the offset log of the
  // operation that produced it (every operation that changes a front counts it again,
  // sorted or not), so one pass marks and scatters.
  void balance(Exec& exec, RadixScratch<Exec>* radix) {
    if (!active_) return;
    if (!radix) {
      auto mark = [&](int k) {
        FrontArrays<Exec>& f = front_[k];
        zero_cursors(exec, f);
        return MarkScatterFrontFn{view(), f.prim.data(), f.node.data(), segment_scatter(f, f.raw_prim, f.raw_node)};
      };
      for_both_kinds(exec, mark(kInternalFront), front_[kInternalFront].size, mark(kExternalFront),
                     front_[kExternalFront].size);
    }
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      if (radix) {
        exec.for_each_n(f.size, MarkFrontFn{view(), f.prim.data(), f.node.data(), f.raw_mark.data()});
        radix_order_front(exec, *radix, f.size, key_bits(k), f.prim.data(), f.node.data(), f.raw_mark.data(),
                          f.raw_prim.data(), f.raw_node.data());
      }
      std::swap(f.prim, f.raw_prim);
      std::swap(f.node, f.raw_node);
    }
    ++revision_;
  }

  // After a read-back: grow each kind whose produced front did not fit, keeping the current
  // front; true if one grew (the caller re-runs the frame's front pass from the untouched
  // current fronts).
  bool grow_if_needed(Exec& exec, const FrontCounters& c) {
    if (!active_) return false;
    bool grew = false;
    for (int k = 0; k < 2; ++k) {
      const size_t need = size_t(c.query[index_].produced[k]);
      grew = reserve_room(exec, k, need, need + need / kRegrowSpareDiv) || grew;
    }
    revision_ += grew;
    return grew;
  }

  // Before a build ahead generates these fronts beside the current ones, or an update ahead
  // updates the current ones into them: room for `expected` nodes of each kind and half
  // again (kAheadSpareDiv), so that the side's work fits and is not run again in the
  // adopting frame unless contact grew past the spare, and for at least `at_least` (an update
  // ahead: what the current fronts' arrays held, sized for the update by their probe,
  // reserve_for_update, before they lent them). True if a buffer grew.
  bool reserve_ahead(Exec& exec, const std::array<size_t, 2>& expected, const std::array<size_t, 2>& at_least) {
    if (!active_) return false;
    bool grew = false;
    for (int k = 0; k < 2; ++k) {
      const size_t need = std::max(at_least[k], expected[k] + expected[k] / kAheadSpareDiv);
      grew = reserve_room(exec, k, need, need) || grew;
    }
    revision_ += grew;
    return grew;
  }

  // Exchanges the produced arrays with `o`'s (FrontArrays::swap_produced): this query's
  // fronts, which only preserve until `o`'s replace them, lend them to `o`, planned on a
  // tree of as many leaves with lent arrays; the exchange again gives them back. The fronts
  // that hold no produced arrays have no capacity until then.
  // To fronts planned with ProducedArrays::lent_as_current they are lent as their current
  // arrays (produce_placed), with the mark and the histogram's counters.
  void lend_produced(FrontQuery& o) {
    for (int k = 0; k < 2; ++k) {
      if (o.produced_ == ProducedArrays::lent_as_current)
        front_[k].swap_produced_with_current(o.front_[k], true);
      else
        front_[k].swap_produced(o.front_[k]);
    }
    ++revision_;
    ++o.revision_;
  }

  // After swap_fronts with fronts placed into lent arrays (lend_produced to
  // ProducedArrays::lent_as_current): this query's fronts are those arrays, with the mark
  // and counters they were lent with, and `o` holds the old current arrays, which become
  // this query's produced arrays; `o` is left holding no front arrays again. Without probes,
  // room ahead for an update, as adopt keeps.
  void take_back_produced(Exec& exec, FrontQuery& o) {
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      f.swap_produced_with_current(o.front_[k], false);
      if (!probed_) reserve_headroom(exec, f, f.size + f.size / 4, f.size + f.size / 2);
    }
    ++revision_;
    ++o.revision_;
  }

  // Exchanges the fronts with `o`'s, each query keeping its trees: fronts generated ahead on
  // a tree built ahead become current as that tree replaces this query's (Lbvh::swap).
  void swap_fronts(FrontQuery& o) {
    for (int k = 0; k < 2; ++k) {
      std::swap(front_[k], o.front_[k]);
      std::swap(dropped_[k], o.dropped_[k]);
      std::swap(appended_[k], o.appended_[k]);
    }
    ++revision_;
    ++o.revision_;
  }

  // The produced fronts become current: ordered ones were scattered into the current
  // arrays already (order, radix_order); unordered ones are the raw arrays, swapped in.
  // Placed fronts (produce_placed) are in their current arrays already, and keep no room
  // here: they take the current fronts' place, and take_back_produced keeps it.
  void adopt(Exec& exec, const FrontCounters& c, bool ordered) {
    if (!active_) return;
    const bool placed = produced_ == ProducedArrays::lent_as_current;
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      if (!ordered && !placed) {
        std::swap(f.prim, f.raw_prim);
        std::swap(f.node, f.raw_node);
      }
      f.size = size_t(c.query[index_].produced[k]);
      dropped_[k] = appended_[k] = 0;
      // Without probes an update may outgrow the front it starts from: room ahead for it.
      if (!probed_ && !placed) reserve_headroom(exec, f, f.size + f.size / 4, f.size + f.size / 2);
    }
    ++revision_;
  }

 private:
  // An operation (`run`, given the sink to produce into) producing fronts that hold no
  // arrays but the current ones (ProducedArrays::lent_as_current), into them. `sorted`: run
  // twice, first only counting each tree node's front nodes (the count log; nothing is
  // stored), then, the count log scanned into the offset log, putting each node at its
  // sorted place (PlacedFrontSink); the traversals run twice, and the unordered copy that an
  // operation and its scatter need, a third set of front arrays beside the current fronts
  // and these, is never held. Otherwise run once, appending to them, counted per tree node
  // where `mode.histogram` (their offset log then follows).
  template <class Run>
  void produce_placed(Exec& exec, Pairs& pairs, const ProduceMode& mode, bool sorted, const Run& run) {
    if (produced_ != ProducedArrays::lent_as_current) fail("fronts that hold produced arrays were placed");
    if (sorted && !mode.histogram) fail("fronts placed in order without their count log");
    if (mode.histogram) zero_order_counts(exec);
    FrontSink append{};
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      append.prim[k] = sorted ? nullptr : f.prim.data();
      append.node[k] = sorted ? nullptr : f.node.data();
      append.mark[k] = sorted ? nullptr : f.raw_mark.data();
      append.capacity[k] = sorted ? 0 : room(k);  // counting: nothing stored
      append.count_log[k] = mode.histogram ? f.count_log() : nullptr;
    }
    append.count = counters(pairs)->produced;
    run(append);
    if (mode.histogram) offsets(exec);
    if (!sorted) return;
    PlacedFrontSink place{};
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      place.offset_log[k] = f.offset_log.data();
      place.cursor_front[k] = f.cursor_front();
      place.cursor_back[k] = f.cursor_back();
      place.prim[k] = f.prim.data();
      place.node[k] = f.node.data();
      place.capacity[k] = room(k);
    }
    place.count = counters(pairs)->produced;
    run(place);
  }

  // Front nodes kind k's arrays hold: for placed fronts, their lent current arrays and mark
  // (they hold no others).
  size_t room(int k) const {
    const FrontArrays<Exec>& f = front_[k];
    if (produced_ != ProducedArrays::lent_as_current) return f.capacity();
    return std::min({f.prim.capacity(), f.node.capacity(), f.raw_mark.capacity()});
  }

  // Kind k's arrays hold `need` nodes, or grow to `want` (reserve_headroom). Placed
  // fronts' lent arrays hold nothing before the side's run writes them whole, so nothing is
  // copied into them.
  bool reserve_room(Exec& exec, int k, size_t need, size_t want) {
    if (produced_ != ProducedArrays::lent_as_current) return reserve_headroom(exec, front_[k], need, want);
    FrontArrays<Exec>& f = front_[k];
    if (room(k) >= need) return false;
    for (auto* a : {&f.prim, &f.node}) a->reserve(want);
    f.raw_mark.reserve(want);
    return true;
  }

  // Nodes an update in place can append to kind k: the room past the front's end, which
  // its raw arrays (where a sorted tail is produced first) hold too.
  size_t append_room(int k) const {
    const FrontArrays<Exec>& f = front_[k];
    return f.capacity() > f.size ? f.capacity() - f.size : 0;
  }

  // The count logs and the scatter's cursors (front.h, order_counts): one fill a kind.
  void zero_order_counts(Exec& exec) {
    for (auto& f : front_) exec.fill(f.order_counts.data(), f.order_counts.size(), 0u);
  }

  // Threads per traversal of a launch of `n` traversals, as a shift (front/warp_traversal.h,
  // "Spread launches"): more than one only where they are shared out in warps.
  static uint32_t spread_shift(const Exec& exec, size_t n, bool share_in_warp, uint64_t waves) {
    return share_in_warp ? spread_shift_for(n, exec.resident_threads(), waves) : 0;
  }

  FrontQueryCounters* counters(Pairs& pairs) const { return &pairs.device()->query[index_]; }

  FrontSink produce_sink(Exec& exec, Pairs& pairs, bool histogram) {
    if (histogram) zero_order_counts(exec);
    FrontSink s{};
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      s.prim[k] = f.raw_prim.data();
      s.node[k] = f.raw_node.data();
      s.mark[k] = f.raw_mark.data();
      s.capacity[k] = f.capacity();
      s.count_log[k] = histogram ? f.count_log() : nullptr;
    }
    s.count = counters(pairs)->produced;
    return s;
  }

  // The passes of a preserve functor over both kinds of front in one launch.
  template <class Fn>
  void preserve_with(Exec& exec, Fn fn, const PreserveLaunch& launch) {
    fn.view = view();
    auto pass = [&](const FrontArrays<Exec>& f) {
      Fn p = fn;
      p.prim = f.prim.data();
      p.node = f.node.data();
      return p;
    };
    const uint32_t shift = spread_shift(exec, total(), fn.share_in_warp, kSpreadWavesPreserve);
    // A probe takes one node a thread: with two it would add its counts twice a warp.
    if constexpr (!Fn::kCounts) {
      if (launch.two_nodes && shift == 0) {
        using Two = PreserveTwoNodesFn<Fn>;
        const Two two{pass(front_[0]), pass(front_[1]), uint32_t(front_[0].size), uint32_t(total())};
        if (launch.staged)
          exec.for_each_staged(Two::threads_for(total()), two, Balance::uneven, launch.occupancy);
        else
          exec.for_each_n(Two::threads_for(total()), two, Balance::uneven, launch.occupancy);
        return;
      }
    }
    const BothFrontsFn<Fn> both{pass(front_[0]), pass(front_[1]), uint32_t(front_[0].size), shift};
    if (launch.staged)
      exec.for_each_staged(total() << shift, both, Balance::uneven, launch.occupancy);
    else
      exec.for_each_n(total() << shift, both, Balance::uneven, launch.occupancy);
  }

  // The arrays of a kind hold `need` nodes, or all grow to `want`, the current front copied
  // into its larger arrays (a frame that overflowed runs again from it). Without probes,
  // after an adopt, `need` is the front with a quarter to spare and `want` with half: the
  // next update, which may sprout more than it prunes, then mostly fits the first time
  // instead of growing and running again (fronts grow by more than a quarter in some single
  // updates). With probes the update is sized before it runs (reserve_for_update), and an
  // adopted front keeps no spare: every front it produced fit already. All five arrays grow
  // together: balance and adopt swap the current arrays with the raw ones. This runs after
  // the frame's read-back, outside its timing, and only when an array is short; true if so.
  static bool reserve_headroom(Exec& exec, FrontArrays<Exec>& f, size_t need, size_t want) {
    if (f.capacity() >= need) return false;
    // The raw arrays hold nothing between frames: they grow first and the current front is
    // copied into them, so each array is allocated once at its new size.
    for (auto* a : {&f.raw_prim, &f.raw_node}) a->reserve(want);
    f.raw_mark.reserve(want);
    for (auto [current, spare] : {std::pair{&f.prim, &f.raw_prim}, std::pair{&f.node, &f.raw_node}}) {
      exec.copy(spare->data(), current->data(), f.size);
      std::swap(*current, *spare);
      spare->reserve(want);
    }
    return true;
  }
  static bool reserve_headroom(Exec& exec, FrontArrays<Exec>& f, size_t need) {
    return reserve_headroom(exec, f, need, need);
  }

  FrontArrays<Exec> front_[2];
  // Per kind, since the front was last produced whole: holes left and nodes appended by
  // updates in place.
  size_t dropped_[2] = {0, 0};
  size_t appended_[2] = {0, 0};
  Lbvh<Exec>* leaves_ = nullptr;
  Lbvh<Exec>* tree_ = nullptr;
  size_t index_;
  uint64_t revision_ = 0;
  bool active_ = false;
  bool in_place_ = false;  // updates may run in place (plan)
  ProducedArrays produced_ = ProducedArrays::own;  // (plan)
  bool probed_ = true;     // updates are sized by probes (plan)
};

}  // namespace cdb
