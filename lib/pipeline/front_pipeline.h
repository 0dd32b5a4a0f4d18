#pragma once
// Front-based pipelines (paper Fig. 4, §5.2) as one state machine over the executor. Each
// frame: refit (or rebuild), then one front operation — (1) generate, (2) preserve,
// (3) update, with (4) balance before it in pipeline b, or (5) restructure in pipeline c —
// decided on the host from the frame counter and, in c, from the counters of the last
// inspection (already read back with that frame's counters). Produced fronts are ordered by
// histogram sort unless the strategy is `unordered`. One read-back a frame: pair, front and
// inspection counters together; an overflow grows the buffer (logged, counted) and re-runs
// the operation from the untouched current front.
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "front/front.h"
#include "front/operations.h"
#include "front/ordering.h"
#include "front/quality.h"
#include "front/radix_ordering.h"
#include "front/restructure_front.h"
#include "pipeline/device_mesh.h"
#include "pipeline/pipeline.h"

namespace cdb {

struct FrontPlan {
  bool ordered = true;             // histogram-sort fronts after producing them
  bool balance = false;            // (4) before every (3)
  bool periodic = false;           // (1) instead of (3) every second cycle
  bool rebuild_every_frame = false;  // the reference strategy
  bool radix_sort = false;  // order fronts and BVH with a radix sort instead of the histogram (Fig. 6 baseline)
  bool restructure = false;  // pipeline c: inspect quality, Formula 2, (5) restructure
};

template <class Exec, class Timer>
class FrontPipeline final : public Pipeline {
 public:
  FrontPipeline(const PipelineConfig& config, FrontPlan plan)
      : config_(config), plan_(plan), timer_(exec_), mesh_(exec_), bvh_(exec_), pairs_(exec_),
        restructure_(exec_) {
    front_[kInternalFront].bind(exec_.memory(), kInternalFront);
    front_[kExternalFront].bind(exec_.memory(), kExternalFront);
    radix_.bind(exec_.memory());
    if (config_.front_cycle == 0) fail("--front-cycle must be at least 1");
    if (plan_.restructure) check_restructure_config(config_);
  }

  void set_topology(const Topology& topology) override {
    mesh_.set_topology(exec_, topology);
    const uint32_t n = mesh_.num_faces();
    pairs_.skip_adjacent(config_.skip_adjacent ? mesh_.face_vertices() : nullptr);
    pairs_.filter_queries(mesh_.face_object(), mesh_.partners());
    bvh_.reserve(exec_, n);
    pairs_.reserve(size_t(config_.pairs_per_triangle * n));
    const size_t cap = std::max<size_t>(1024, size_t(config_.front_per_triangle * n));
    front_[kInternalFront].reserve(cap, n > 1 ? n - 1 : 1);
    front_[kExternalFront].reserve(cap, std::max<uint32_t>(n, 1));
    if (plan_.radix_sort) radix_.reserve(exec_, cap);
    if (plan_.restructure) restructure_.reserve(exec_, n, config_.restructure_min_leaves);
    frame_ = 0;
    pending_ = {};
    q_ref_ = 0.0;
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    FrameStats stats;
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    const Decision decision = decide(stats);
    const bool rebuild = frame_ == 0 || plan_.rebuild_every_frame || decision == Decision::rebuild ||
                         (config_.rebuild_every > 0 && frame_ % config_.rebuild_every == 0);
    stats.op = update_hierarchy(exec_, timer_, bvh_, mesh, rebuild, config_.morton_bits, plan_.radix_sort);
    if (rebuild) generated_at_ = frame_;
    const Op op = !rebuild && decision == Decision::restructure ? Op::restructure : choose_op(rebuild);
    if (op == Op::update && plan_.balance) balance();
    if (op == Op::restructure) restructure_tree_and_classify_fronts();
    // Inspected after update (the paper's circle 3) only: right after a rebuild Q is the
    // reference, and a restructure keeps the stale front for the next update to refresh.
    const bool inspect = plan_.restructure && q_ref_ > 0.0 && op == Op::update;
    for (;;) {
      pairs_.reset_counters(exec_);
      run_op(op);
      if (inspect) inspect_quality();
      timer_.stop_frame();
      const auto c = pairs_.read_counters(exec_);
      bool again = pairs_.grow_if_needed();
      if (op != Op::preserve) again = grow_front_if_needed(c) || again;
      if (!again) {
        if (op != Op::preserve) adopt_produced_front(c);
        break;
      }
      ++stats.query_reruns;
    }
    if (op == Op::generate) generated_at_ = frame_;
    stats.op += std::string("+") + op_name(op);
    stats.pairs = pairs_.count();
    stats.front_internal = front_[kInternalFront].size;
    stats.front_external = front_[kExternalFront].size;
    stats.q_root = plan_.ordered && stats.front_external
                       ? double(stats.front_internal) / double(stats.front_external)
                       : 0.0;
    if (plan_.restructure && rebuild) q_ref_ = stats.q_root;
    if (inspect) {
      const auto c = pairs_.last_counters();
      pending_.count = uint32_t(std::min<unsigned long long>(c[4], restructure_.max_candidates));
      pending_.leaves = uint32_t(c[5]);
      stats.candidates = c[4];
      stats.candidate_leaves = c[5];
      stats.q_candidates = c[4] ? double(c[6]) / 1000.0 / double(c[4]) : 0.0;
    }
    record_timings(timer_, stats);
    ++frame_;
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  enum class Op { generate, preserve, update, restructure };
  static const char* op_name(Op op) {
    return op == Op::generate   ? "generate"
           : op == Op::preserve ? "preserve"
           : op == Op::update   ? "update"
                                : "restructure";
  }

  enum class Decision { none, refit, restructure, rebuild };

  static void check_restructure_config(const PipelineConfig& c) {
    if (c.restructure_min_leaves < 2) fail("--restructure-min-leaves must be at least 2");
    if (!(c.restructure_max_fraction > 0.0 && c.restructure_max_fraction <= 1.0))
      fail("--restructure-max-fraction must be in (0, 1]");
    if (!(c.restructure_quality >= 0.0)) fail("--restructure-quality must be at least 0");
    if (!(c.threshold_refit >= 0.0) || !(c.threshold_build >= c.threshold_refit))
      fail("thresholds must satisfy 0 <= --threshold-refit <= --threshold-build");
  }

  // Formula 2 (paper §4.2) on the candidates of the last inspection, as a share of the
  // leaves. The paper prints the rebuild and restructure branches the other way round;
  // restructuring many subtrees costs more than a rebuild and restructuring few is what it
  // is for, so here a large share rebuilds (docs/design.md).
  Decision decide(FrameStats& stats) {
    if (!plan_.restructure || pending_.count == 0) return Decision::none;
    const double share = double(pending_.leaves) / double(std::max<uint32_t>(bvh_.num_leaves, 1));
    const Decision d = share < config_.threshold_refit   ? Decision::refit
                       : share < config_.threshold_build ? Decision::restructure
                                                         : Decision::rebuild;
    stats.decision = d == Decision::refit ? "refit" : d == Decision::restructure ? "restructure" : "rebuild";
    restructuring_ = pending_;
    pending_ = {};
    return d;
  }

  // (5), first half: candidates described from the refitted tree, fronts classified against
  // the old node ranges, then the candidate subtrees rebuilt. The front pass that follows
  // (run_op) may be re-run on overflow; this part must not be.
  void restructure_tree_and_classify_fronts() {
    timer_.start(Phase::restructure);
    describe_candidates(exec_, bvh_, restructure_, restructuring_.count);
    const CandidateView cand = restructure_.view();
    for (int k = 0; k < 2; ++k)
      exec_.for_each_n(front_[k].size, ClassifyFrontFn{bvh_.node_first.data(), bvh_.node_last.data(),
                                                       cand, front_[k].prim.data(),
                                                       front_[k].node.data()});
    restructure_subtrees(exec_, bvh_, restructure_, restructuring_.count, restructuring_.leaves);
    timer_.stop(Phase::restructure);
  }

  void inspect_quality() {
    const uint32_t n = bvh_.num_leaves;
    if (n < 2) return;
    timer_.start(Phase::inspect);
    const uint32_t max_leaves = std::max<uint32_t>(
        config_.restructure_min_leaves, uint32_t(config_.restructure_max_fraction * double(n)));
    exec_.for_each_n(n - 1, InspectQualityFn{bvh_.node_first.data(), bvh_.node_last.data(),
                                             bvh_.node_parent.data(),
                                             front_[kInternalFront].offset_log.data(),
                                             front_[kExternalFront].offset_log.data(),
                                             float(config_.restructure_quality * q_ref_),
                                             config_.restructure_min_leaves, max_leaves,
                                             restructure_.max_candidates, restructure_.node.data(),
                                             pairs_.counter(4)});
    timer_.stop(Phase::inspect);
  }

  Op choose_op(bool rebuilt) const {
    if (rebuilt) return Op::generate;
    const uint64_t since = frame_ - generated_at_;
    if (since % config_.front_cycle != 0) return Op::preserve;
    if (plan_.periodic && (since / config_.front_cycle) % 2 == 0) return Op::generate;
    return Op::update;
  }

  FrontTree tree() const {
    return {bvh_.view(), bvh_.leaf_parent.data(), bvh_.node_parent.data()};
  }

  FrontSink produce_sink() {
    FrontSink s{};
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      s.prim[k] = f.raw_prim.data();
      s.node[k] = f.raw_node.data();
      s.mark[k] = f.raw_mark.data();
      s.capacity[k] = f.raw_prim.capacity();
      s.count_log[k] = histogram_sorted() ? f.count_log.data() : nullptr;
    }
    s.count = pairs_.counter(1);
    return s;
  }

  size_t segments(int k) const {
    const uint32_t n = bvh_.num_leaves;
    return k == kInternalFront ? (n > 1 ? n - 1 : 0) : n;
  }

  bool histogram_sorted() const { return plan_.ordered && !plan_.radix_sort; }

  void zero_count_logs() {
    for (int k = 0; k < 2; ++k) exec_.fill(front_[k].count_log.data(), segments(k) + 1, 0u);
  }

  void run_op(Op op) {
    const FrontTree t = tree();
    const uint32_t n = bvh_.num_leaves;
    if (op == Op::preserve) {
      timer_.start(Phase::preserve);
      for (int k = 0; k < 2; ++k)
        exec_.for_each_n(front_[k].size, PreserveFrontFn{t, pairs_.sink(), front_[k].prim.data(),
                                                         front_[k].node.data()},
                         Balance::uneven);
      timer_.stop(Phase::preserve);
      return;
    }
    const Phase phase = op == Op::generate      ? Phase::generate
                        : op == Op::restructure ? Phase::restructure
                                                : Phase::update;
    timer_.start(phase);
    if (histogram_sorted()) zero_count_logs();
    const FrontSink sink = produce_sink();
    if (op == Op::generate) {
      exec_.for_each_n(n, GenerateFrontFn{t, pairs_.sink(), sink}, Balance::uneven);
    } else if (op == Op::restructure) {
      for (int k = 0; k < 2; ++k)
        exec_.for_each_n(front_[k].size,
                         RestructureFrontFn{t, pairs_.sink(), sink, restructure_.view(),
                                            front_[k].prim.data(), front_[k].node.data()},
                         Balance::uneven);
    } else {
      for (int k = 0; k < 2; ++k)
        exec_.for_each_n(front_[k].size, UpdateFrontFn{t, pairs_.sink(), sink, front_[k].prim.data(),
                                                       front_[k].node.data()},
                         Balance::uneven);
    }
    timer_.stop(phase);
    if (!plan_.ordered) return;
    if (plan_.radix_sort) {
      // The sort needs the produced sizes on the host: one more read-back on these frames.
      const auto c = pairs_.read_counters(exec_);
      timer_.start(Phase::front_order);
      for (int k = 0; k < 2; ++k) {
        FrontArrays<Exec>& f = front_[k];
        if (c[1 + k] <= f.raw_prim.capacity())
          radix_order_front(exec_, f, radix_, size_t(c[1 + k]), key_bits(k), f.raw_prim.data(),
                            f.raw_node.data(), f.raw_mark.data());
      }
      timer_.stop(Phase::front_order);
      return;
    }
    timer_.start(Phase::front_order);
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      order_front(exec_, f, segments(k), pairs_.counter(1 + k), f.raw_prim.data(), f.raw_node.data(),
                  f.raw_mark.data(), f.raw_prim.capacity(), bvh_.temp.data(), bvh_.temp.size());
    }
    timer_.stop(Phase::front_order);
  }

  int key_bits(int k) const {
    int bits = 1;
    while (bits < 63 && (uint64_t(1) << bits) < 2 * uint64_t(segments(k)) + 2) ++bits;
    return bits;
  }

  // (4) Balance: mark each current front node with the branch it will take, then reorder
  // the current front by node key and mark. The front's content is unchanged.
  void balance() {
    timer_.start(Phase::balance);
    const FrontTree t = tree();
    if (histogram_sorted()) zero_count_logs();
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      exec_.for_each_n(f.size, MarkFrontFn{t, f.prim.data(), f.node.data(), f.raw_mark.data(),
                                           histogram_sorted() ? f.count_log.data() : nullptr});
      if (plan_.radix_sort) {
        radix_order_front(exec_, f, radix_, f.size, key_bits(k), f.prim.data(), f.node.data(),
                          f.raw_mark.data());
      } else {
        exec_.fill(pairs_.counter(3), 1, static_cast<unsigned long long>(f.size));
        order_front(exec_, f, segments(k), pairs_.counter(3), f.prim.data(), f.node.data(),
                    f.raw_mark.data(), f.size, bvh_.temp.data(), bvh_.temp.size());
      }
      std::swap(f.prim, f.sorted_prim);
      std::swap(f.node, f.sorted_node);
      match_capacity(f);
    }
    timer_.stop(Phase::balance);
  }

  bool grow_front_if_needed(const std::array<unsigned long long, PairBuffer<Exec>::kCounters>& c) {
    bool grew = false;
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      const unsigned long long need = c[1 + k];
      if (need <= f.raw_prim.capacity()) continue;
      const size_t cap = size_t(need + need / 4);
      for (auto* a : {&f.raw_prim, &f.raw_node, &f.sorted_prim, &f.sorted_node}) a->reserve(cap);
      f.raw_mark.reserve(cap);
      grew = true;
    }
    return grew;
  }

  void adopt_produced_front(const std::array<unsigned long long, PairBuffer<Exec>::kCounters>& c) {
    for (int k = 0; k < 2; ++k) {
      FrontArrays<Exec>& f = front_[k];
      if (plan_.ordered) {
        std::swap(f.prim, f.sorted_prim);
        std::swap(f.node, f.sorted_node);
      } else {
        std::swap(f.prim, f.raw_prim);
        std::swap(f.node, f.raw_node);
      }
      f.size = size_t(c[1 + k]);
      match_capacity(f);
    }
  }

  // Scratch buffers swapped with the current front keep up with its capacity, so a front
  // that grew does not make its next operation overflow again. Contents are scratch.
  void match_capacity(FrontArrays<Exec>& f) {
    const size_t cap = std::max({f.prim.capacity(), f.raw_prim.capacity(), f.sorted_prim.capacity()});
    for (auto* a : {&f.raw_prim, &f.raw_node, &f.sorted_prim, &f.sorted_node})
      if (a->capacity() < cap) a->reserve(cap);
    if (f.raw_mark.capacity() < cap) f.raw_mark.reserve(cap);
  }

  PipelineConfig config_;
  FrontPlan plan_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  Lbvh<Exec> bvh_;
  PairBuffer<Exec> pairs_;
  FrontArrays<Exec> front_[2];
  RadixScratch<Exec> radix_;
  RestructureScratch<Exec> restructure_;
  struct Candidates {
    uint32_t count = 0, leaves = 0;
  };
  Candidates pending_;        // found by the last inspection, decided on next frame
  Candidates restructuring_;  // being restructured this frame
  double q_ref_ = 0.0;        // Q of the root after the last rebuild (pipeline c)
  uint64_t frame_ = 0, generated_at_ = 0;
};

}  // namespace cdb
