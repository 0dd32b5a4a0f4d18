#pragma once
// Front-based pipelines (paper Fig. 4, §5.2) as one state machine over the executor. Each
// frame: refit (or rebuild), then one front operation — (1) generate, (2) preserve,
// (3) update, with (4) balance before it in pipeline b, or (5) restructure in pipeline c —
// decided on the host from the frame counter and, in c, from the counters of the last
// inspection (already read back with that frame's counters). Produced fronts are ordered by
// histogram sort unless the strategy is `unordered`. One read-back a frame: pair, front and
// inspection counters together; an overflow grows the buffer (logged, counted) and re-runs
// the operation from the untouched current front.
//
// A scene with declared queries and rigid objects is split (geometry/object_split.h): T_D
// over the deformable faces follows this state machine; T_R over the rigid faces is built
// on the first frame and only refitted after (rigid motion keeps a tree's quality). Up to
// three front queries run each frame, each only when a declared query needs it: the self
// fronts of T_D, the cross fronts of T_D's leaves against T_R, and the self fronts of T_R.
// Unsplit, T_D holds every face and only its self fronts run.
#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "front/quality.h"
#include "pipeline/device_mesh.h"
#include "pipeline/front_query.h"
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
      : config_(config), plan_(plan), exec_(ExecOptions{config.dependent_launch}),
        timer_(exec_, config.phase_timing), mesh_(exec_), bvh_(exec_),
        rigid_bvh_(exec_, "rigid_bvh"), pairs_(exec_), restructure_(exec_),
        self_(exec_, "front", kSelfCounters), inter_(exec_, "inter_front", kInterCounters),
        rigid_self_(exec_, "rigid_front", kRigidCounters) {
    radix_.bind(exec_.memory());
    if (config_.front_cycle == 0) fail("--front-cycle must be at least 1");
    if (config_.refit_every == 0) fail("--refit-every must be at least 1");
    mesh_.set_box_knobs(config_);
    if (plan_.restructure) check_restructure_config(config_);
  }

  void set_topology(const Topology& topology) override {
    mesh_.set_topology(exec_, topology);
    const ObjectSplit& split = mesh_.split();
    pairs_.skip_adjacent(config_.skip_adjacent ? mesh_.face_vertices() : nullptr);
    pairs_.filter_queries(mesh_.face_object(), mesh_.partners());
    pairs_.reserve(size_t(config_.pairs_per_triangle * mesh_.num_faces()));
    bvh_.refit_top_max_leaves = rigid_bvh_.refit_top_max_leaves = config_.refit_top_leaves;
    bvh_.reserve(exec_, mesh_.deformable().count);
    rigid_bvh_.reserve(exec_, mesh_.rigid().count);
    self_.plan(bvh_, bvh_, split.deformable_self, config_.front_per_triangle);
    inter_.plan(bvh_, rigid_bvh_, split.cross, config_.front_per_triangle);
    rigid_self_.plan(rigid_bvh_, rigid_bvh_, split.rigid_self, config_.front_per_triangle);
    if (plan_.radix_sort)
      radix_.reserve(exec_, std::max({self_.capacity(), inter_.capacity(), rigid_self_.capacity()}));
    if (plan_.restructure) restructure_.reserve(exec_, bvh_.num_leaves, config_.restructure_min_leaves);
    frame_ = 0;
    stage_preserve_ = true;
    warp_preserve_ = true;
    pending_ = {};
    q_ref_ = 0.0;
    ++graph_version_;
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    FrameStats stats;
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    const Decision decision = decide(stats);
    const bool rebuild = frame_ == 0 || plan_.rebuild_every_frame || decision == Decision::rebuild ||
                         (config_.rebuild_every > 0 && frame_ % config_.rebuild_every == 0);
    // --refit-every: between refits both trees keep their last boxes (not conservative).
    const bool stale = !rebuild && !refit_due(frame_, config_.refit_every);
    if (rebuild) generated_at_ = frame_;
    const Ops ops = choose_ops(rebuild, !rebuild && decision == Decision::restructure);
    // The steady state: every query preserves its fronts, so the frame launches what the
    // last steady frame launched, unless a buffer or a front changed since (graph_version_).
    const bool steady = !rebuild && ops.self == Op::preserve && ops.inter == Op::preserve &&
                        ops.rigid_self == Op::preserve;
    if (!steady) {
      ++graph_version_;
      stats.op = stale ? "stale" : update_trees(mesh, rebuild);
    } else {
      stats.op = stale ? "stale" : "refit";
    }
    if (plan_.balance) balance(ops);
    if (ops.self == Op::restructure) restructure_tree_and_classify_fronts();
    // Inspected after update (the paper's circle 3) only: right after a rebuild Q is the
    // reference, and a restructure keeps the stale front for the next update to refresh.
    const bool inspect = plan_.restructure && q_ref_ > 0.0 && ops.self == Op::update;
    for (bool first_pass = true;; first_pass = false) {
      if (steady && first_pass) {
        stats.graph = frame_graph_run_name(run_steady(mesh, stale, ops));
      } else {
        pairs_.reset_counters(exec_);
        run_ops(ops);
      }
      if (inspect) inspect_quality();
      timer_.stop_frame();
      const auto c = pairs_.read_counters(exec_);
      bool again = pairs_.grow_if_needed();
      for (Query q : kQueries)
        if (ops.of(q) != Op::preserve) again = query(q).grow_if_needed(c) || again;
      if (!again) {
        for (Query q : kQueries)
          if (ops.of(q) != Op::preserve) query(q).adopt(c, plan_.ordered);
        break;
      }
      ++graph_version_;
      ++stats.query_reruns;
    }
    if (ops.self == Op::generate) generated_at_ = frame_;
    stats.op += std::string("+") + op_name(ops.self);
    stats.pairs = pairs_.count();
    stats.front_internal = self_.size(kInternalFront);
    stats.front_external = self_.size(kExternalFront);
    stats.front_inter = inter_.total();
    stats.front_rigid = rigid_self_.total();
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
    choose_preserve_launch(stats.pairs);
    ++frame_;
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  // The pair buffer's counters: [0] pairs, [4..6] the inspection's ([3] is free);
  // each front query counts its produced internal and external fronts in two more.
  static constexpr size_t kSelfCounters = 1, kInterCounters = 7, kRigidCounters = 9;
  static_assert(kRigidCounters + 2 <= PairBuffer<Exec>::kCounters, "front counters past the block");

  enum class Op { generate, preserve, update, restructure };
  static const char* op_name(Op op) {
    return op == Op::generate   ? "generate"
           : op == Op::preserve ? "preserve"
           : op == Op::update   ? "update"
                                : "restructure";
  }

  enum class Query { self, inter, rigid_self };
  static constexpr std::array<Query, 3> kQueries = {Query::self, Query::inter, Query::rigid_self};
  FrontQuery<Exec>& query(Query q) {
    return q == Query::self ? self_ : q == Query::inter ? inter_ : rigid_self_;
  }

  // The operation of each front query this frame.
  struct Ops {
    Op self, inter, rigid_self;
    Op of(Query q) const { return q == Query::self ? self : q == Query::inter ? inter : rigid_self; }
  };

  enum class Decision { none, refit, restructure, rebuild };

  // Refit or rebuild T_D; T_R is built on the first frame and refitted after.
  std::string update_trees(const MeshView& mesh, bool rebuild) {
    const std::string op = update_hierarchy(exec_, timer_, bvh_, mesh, mesh_.deformable(), rebuild,
                                            config_.morton_bits, plan_.radix_sort);
    update_hierarchy(exec_, timer_, rigid_bvh_, mesh, mesh_.rigid(), frame_ == 0, config_.morton_bits,
                     plan_.radix_sort, mesh_.face_object());
    return op;
  }

  // A steady frame's refit of both trees; T_D's zeroes the pair buffer's counters on its
  // way, which saves the frame a launch. True if it did.
  bool refit_trees(const MeshView& mesh) {
    timer_.start(Phase::refit);
    const bool zeroed = refit(exec_, bvh_, mesh, pairs_.counter_reset());
    refit(exec_, rigid_bvh_, mesh);
    timer_.stop(Phase::refit);
    return zeroed;
  }

  // A steady frame's work (refit unless stale, counters, preserve), through the frame graph
  // with --cuda-graph. The key holds what the launches depend on besides graph_version_:
  // the vertex buffers (swept boxes alternate them) and whether the frame refits.
  FrameGraphRun run_steady(const MeshView& mesh, bool stale, const Ops& ops) {
    auto launch = [&] {
      if (stale || !refit_trees(mesh)) pairs_.reset_counters(exec_);
      run_ops(ops);
    };
    if (!config_.cuda_graph) {
      launch();
      return FrameGraphRun::plain;
    }
    const FrameGraphKey key{graph_version_, uint64_t(reinterpret_cast<uintptr_t>(mesh.vertices)),
                            uint64_t(reinterpret_cast<uintptr_t>(mesh.prev_vertices)), stale ? 1u : 0u};
    return graph_.run(exec_, timer_, key, launch);
  }

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

  // (5), first half: candidates described from the refitted T_D, its self fronts
  // classified against the old node ranges, then the candidate subtrees rebuilt. The front
  // pass that follows (run_ops) may be re-run on overflow; this part must not be.
  void restructure_tree_and_classify_fronts() {
    timer_.start(Phase::restructure);
    describe_candidates(exec_, bvh_, restructure_, restructuring_.count);
    self_.classify(exec_, restructure_.view());
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
                                             self_.front(kInternalFront).offset_log.data(),
                                             self_.front(kExternalFront).offset_log.data(),
                                             float(config_.restructure_quality * q_ref_),
                                             config_.restructure_min_leaves, max_leaves,
                                             restructure_.max_candidates, restructure_.node.data(),
                                             pairs_.counter(4)});
    timer_.stop(Phase::inspect);
  }

  // The self fronts of T_D follow the cycle, or restructure. The cross fronts name T_D's
  // leaves, which a rebuild or a restructure renumbers: they regenerate then, and otherwise
  // follow the cycle. T_R is only refitted after its build, so its self fronts follow the
  // cycle (generating when T_D rebuilds, with everything else).
  Ops choose_ops(bool rebuilt, bool restructure) const {
    const Op cycle = choose_op(rebuilt);
    return {restructure ? Op::restructure : cycle, restructure ? Op::generate : cycle, cycle};
  }

  Op choose_op(bool rebuilt) const {
    if (rebuilt) return Op::generate;
    const uint64_t since = frame_ - generated_at_;
    if (since % config_.front_cycle != 0) return Op::preserve;
    if (plan_.periodic && (since / config_.front_cycle) % 2 == 0) return Op::generate;
    return Op::update;
  }

  bool histogram_sorted() const { return plan_.ordered && !plan_.radix_sort; }

  static Phase phase_of(Op op) {
    return op == Op::generate      ? Phase::generate
           : op == Op::preserve    ? Phase::preserve
           : op == Op::restructure ? Phase::restructure
                                   : Phase::update;
  }

  // Every active query's operation, then the ordering of the fronts they produced.
  void run_ops(const Ops& ops) {
    const bool histogram = histogram_sorted();
    bool produced = false;
    for (Query q : kQueries) {
      FrontQuery<Exec>& fq = query(q);
      const Op op = ops.of(q);
      if (!fq.active()) continue;
      timer_.start(phase_of(op));
      switch (op) {
        case Op::preserve:
          fq.preserve(exec_, pairs_, stage_preserve_, warp_preserve_);
          break;
        case Op::generate:
          fq.generate(exec_, pairs_, histogram);
          break;
        case Op::update:
          fq.update(exec_, pairs_, histogram);
          break;
        case Op::restructure:
          fq.restructure(exec_, pairs_, histogram, restructure_.view());
          break;
      }
      timer_.stop(phase_of(op));
      produced = produced || op != Op::preserve;
    }
    if (!plan_.ordered || !produced) return;
    if (plan_.radix_sort) {
      // The sort needs the produced sizes on the host: one more read-back on these frames.
      const auto c = pairs_.read_counters(exec_);
      timer_.start(Phase::front_order);
      for (Query q : kQueries)
        if (ops.of(q) != Op::preserve) query(q).radix_order(exec_, radix_, c);
      timer_.stop(Phase::front_order);
      return;
    }
    timer_.start(Phase::front_order);
    for (Query q : kQueries)
      if (ops.of(q) != Op::preserve) query(q).order(exec_, pairs_);
    timer_.stop(Phase::front_order);
  }

  // Preserve stages its pairs per block while blocks produce enough of them to pay for the
  // stage's flush (core/append_stage.h): at least kStagedPairsPerBlock per block of front
  // nodes in the frame just read back (cloth scenes 60-90, n-body 11 on the H100). A change
  // is a different launch, so the steady frame's graph is recorded again.
  // The traversals are shared within warps as --preserve-warp says (PreserveWarp).
  static constexpr uint64_t kStagedPairsPerBlock = 32;
  void choose_preserve_launch(uint64_t pairs) {
    const uint64_t fronts = self_.total() + inter_.total() + rigid_self_.total();
    const bool stage = pairs * kStagedThreads >= kStagedPairsPerBlock * fronts;
    const bool warp = config_.preserve_warp == PreserveWarp::on ||
                      (config_.preserve_warp == PreserveWarp::automatic &&
                       fronts <= kPreserveWarpWaves * exec_.resident_threads());
    if (stage != stage_preserve_ || warp != warp_preserve_) ++graph_version_;
    stage_preserve_ = stage;
    warp_preserve_ = warp;
  }

  // (4) Balance, before each update: the fronts' content is unchanged.
  void balance(const Ops& ops) {
    bool any = false;
    for (Query q : kQueries) any = any || (ops.of(q) == Op::update && query(q).active());
    if (!any) return;
    timer_.start(Phase::balance);
    for (Query q : kQueries)
      if (ops.of(q) == Op::update)
        query(q).balance(exec_, plan_.radix_sort ? &radix_ : nullptr);
    timer_.stop(Phase::balance);
  }

  PipelineConfig config_;
  FrontPlan plan_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  Lbvh<Exec> bvh_;        // T_D: the deformable faces, or every face of an unsplit scene
  Lbvh<Exec> rigid_bvh_;  // T_R: the rigid faces (empty unless a query needs them)
  PairBuffer<Exec> pairs_;
  RadixScratch<Exec> radix_;
  RestructureScratch<Exec> restructure_;
  FrontQuery<Exec> self_;        // T_D's leaves against T_D
  FrontQuery<Exec> inter_;       // T_D's leaves against T_R
  FrontQuery<Exec> rigid_self_;  // T_R's leaves against T_R
  struct Candidates {
    uint32_t count = 0, leaves = 0;
  };
  Candidates pending_;        // found by the last inspection, decided on next frame
  Candidates restructuring_;  // being restructured this frame
  double q_ref_ = 0.0;        // Q of the root after the last rebuild (pipeline c)
  uint64_t frame_ = 0, generated_at_ = 0;
  typename Exec::FrameGraph graph_;  // the steady frame's recording (--cuda-graph)
  uint64_t graph_version_ = 0;       // changes whenever fronts or buffers may have
  bool stage_preserve_ = true;  // preserve's pairs staged per block (choose_preserve_launch)
  bool warp_preserve_ = true;   // preserve's traversals shared within warps (choose_preserve_launch)
};

}  // namespace cdb
