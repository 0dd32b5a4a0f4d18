#pragma once
// Front-based pipelines (paper Fig. 4, §5.2): the executor of the frame plans that
// FramePlanner (pipeline/frame_plan.h) decides. Each frame: refit (or rebuild), then one
// front operation per query — (1) generate, (2) preserve, (3) update, with (4) balance
// before it in pipelines b and c, or (5) restructure in c. Produced fronts are ordered by
// histogram sort unless the strategy is `unordered`. One read-back a frame: pair, front and
// inspection counters together; an overflow grows the buffer (counted, listed after the
// run) and re-runs the operation from the untouched current front. The steady frame (refit
// + preserve) replays a CUDA graph while nothing it launches changed. With --order-updates
// off an update's front is kept as produced (counted per node where balance or inspection
// reads the counts) and only generated and restructured fronts are sorted. With
// --update-in-place an update writes into the current fronts (holes and an appended tail)
// until their order has decayed by --compact-share; a re-run after an overflow preserves
// such fronts, or generates one whose appends did not fit.
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
#include "pipeline/front_counters.h"
#include "pipeline/frame_plan.h"
#include "pipeline/front_query.h"
#include "pipeline/pipeline.h"

namespace cdb {

template <class Exec, class Timer>
class FrontPipeline final : public Pipeline {
 public:
  FrontPipeline(const PipelineConfig& config, FrontStrategy chosen)
      : Pipeline(config.box_precision), config_(config), planner_(chosen, config), exec_(ExecOptions{config.dependent_launch}),
        timer_(exec_, config.phase_timing), mesh_(exec_), bvh_(exec_),
        rigid_bvh_(exec_, "rigid_bvh"), pairs_(exec_), restructure_(exec_),
        self_(exec_, "front", 0), inter_(exec_, "inter_front", 1), rigid_self_(exec_, "rigid_front", 2) {
    radix_.bind(exec_.memory());
    if (config_.refit_every == 0) fail("--refit-every must be at least 1");
    mesh_.set_box_knobs(config_);
    if (strategy().restructure) check_restructure_config(config_);
  }

  using Pipeline::run_frame;

  void set_topology(const Topology& topology) override {
    restart_rounding();
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
    if (strategy().radix_sort)
      radix_.reserve(exec_, std::max({self_.capacity(), inter_.capacity(), rigid_self_.capacity()}));
    if (strategy().restructure) restructure_.reserve(exec_, bvh_.num_leaves, config_.restructure_min_leaves);
    planner_.reset();
    stage_preserve_ = true;
    warp_preserve_ = true;
    ++graph_version_;
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    FrameStats stats;
    if (pairs_.reserve_ahead()) ++graph_version_;
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    const uint64_t fronts = self_.total() + inter_.total() + rigid_self_.total();
    const FramePlan plan = planner_.plan(bvh_.num_leaves, fronts, disorder());
    stats.decision = formula2_name(plan.decision);
    // The steady state launches what the last steady frame launched, unless a buffer or a
    // front changed since (graph_version_).
    const bool steady = plan.steady();
    if (!steady) {
      ++graph_version_;
      stats.op = plan.stale ? "stale" : update_trees(mesh, plan.rebuild);
    } else {
      stats.op = plan.stale ? "stale" : "refit";
    }
    if (plan.balance) balance(plan);
    if (plan.self == FrontOp::restructure) restructure_tree_and_classify_fronts(plan.restructuring);
    // The first frame's generate is timed, phases on or off, where maintenances may
    // generate: what a generate costs bounds a maintenance generate before one ran
    // (FrontMaintenance::generate_due). The first frame is left out of every summary, so its
    // events cost the timed frames nothing.
    const bool time_generate = planner_.frame() == 0 && planner_.maintenance().regenerates();
    timer_.force_phases(time_generate);
    // What runs: the plan, then on a re-run each query's fronts as they stand.
    FramePlan run = plan;
    for (bool first_pass = true;; first_pass = false) {
      if (steady && first_pass) {
        stats.graph = frame_graph_run_name(run_steady(mesh, run));
      } else {
        pairs_.reset_counters(exec_);
        run_ops(run);
      }
      if (run.inspect) inspect_quality();
      timer_.stop_frame();
      const FrontCounters& c = pairs_.read_counters(exec_);
      bool again = pairs_.grow_if_needed();
      // Fronts updated in place are current already: a re-run preserves them. One whose
      // appends did not fit is incomplete and is generated again.
      for (Query q : kQueries) {
        if (!patches(run, q)) continue;
        const bool kept = query(q).adopt_patch(exec_, c);
        op_of(run, q) = kept ? FrontOp::preserve : FrontOp::generate;
        again = again || !kept;
      }
      for (Query q : kQueries)
        if (op_of(run, q) != FrontOp::preserve) again = query(q).grow_if_needed(c) || again;
      if (!again) {
        for (Query q : kQueries)
          if (op_of(run, q) != FrontOp::preserve) query(q).adopt(exec_, c, sorts(op_of(run, q)));
        if (plan.probe) reserve_for_update(plan, c);
        break;
      }
      ++graph_version_;
      ++stats.query_reruns;
    }
    timer_.force_phases(false);
    stats.op += std::string("+") + (patches(plan, Query::self) ? "update-in-place" : front_op_name(plan.self));
    stats.pairs = pairs_.count();
    stats.front_internal = self_.live(kInternalFront);
    stats.front_external = self_.live(kExternalFront);
    stats.front_inter = inter_.live_total();
    stats.front_rigid = rigid_self_.live_total();
    stats.front_disorder = disorder();
    stats.q_root = strategy().ordered && stats.front_external
                       ? double(stats.front_internal) / double(stats.front_external)
                       : 0.0;
    Candidates found;
    if (plan.inspect) {
      const InspectCounters& c = pairs_.last_counters().inspect;
      found.count = uint32_t(std::min<unsigned long long>(c.candidates, restructure_.max_candidates));
      found.leaves = uint32_t(c.candidate_leaves);
      stats.candidates = c.candidates;
      stats.candidate_leaves = c.candidate_leaves;
      stats.q_candidates = c.candidates ? double(c.candidate_q_milli) / 1000.0 / double(c.candidates) : 0.0;
    }
    record_timings(timer_, stats);
    // The build frame's generate and its ordering, per front node produced (a re-run after a
    // buffer grew ran them again); not reported unless phases are timed.
    double generate_per_node = -1.0;
    if (time_generate) {
      double& gen = stats.phase_ms[size_t(Phase::generate)];
      double& order = stats.phase_ms[size_t(Phase::front_order)];
      const uint64_t produced = stats.front_internal + stats.front_external + stats.front_inter + stats.front_rigid;
      generate_per_node = (gen + order) / double(1 + stats.query_reruns) / double(std::max<uint64_t>(produced, 1));
      if (!config_.phase_timing) gen = order = 0.0;
    }
    planner_.finish(plan, {stats.total_ms, stats.query_reruns == 0, fronts, stats.q_root, found, stats.graph == "captured",
                           generate_per_node});
    choose_preserve_launch(stats.pairs);
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  enum class Query { self, inter, rigid_self };
  static constexpr std::array<Query, 3> kQueries = {Query::self, Query::inter, Query::rigid_self};
  FrontQuery<Exec>& query(Query q) {
    return q == Query::self ? self_ : q == Query::inter ? inter_ : rigid_self_;
  }

  const FrontStrategy& strategy() const { return planner_.strategy(); }

  static FrontOp op_of(const FramePlan& p, Query q) {
    return q == Query::self ? p.self : q == Query::inter ? p.inter : p.rigid_self;
  }
  static FrontOp& op_of(FramePlan& p, Query q) {
    return q == Query::self ? p.self : q == Query::inter ? p.inter : p.rigid_self;
  }
  // How far updates in place have decayed the fronts' order: the most of any query.
  double disorder() const { return std::max({self_.disorder(), inter_.disorder(), rigid_self_.disorder()}); }

  // Whether query q updates its fronts in place (PatchFrontFn), or produces new ones.
  static bool patches(const FramePlan& p, Query q) { return p.in_place && op_of(p, q) == FrontOp::update; }
  static bool produces(const FramePlan& p, Query q) { return op_of(p, q) != FrontOp::preserve && !patches(p, q); }

  // Refit or rebuild T_D; T_R is built on the first frame and refitted after.
  std::string update_trees(const MeshView& mesh, bool rebuild) {
    const std::string op = update_hierarchy(exec_, timer_, bvh_, mesh, mesh_.deformable(), rebuild,
                                            config_.morton_bits, strategy().radix_sort);
    update_hierarchy(exec_, timer_, rigid_bvh_, mesh, mesh_.rigid(), planner_.frame() == 0,
                     config_.morton_bits, strategy().radix_sort, mesh_.face_object());
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
  FrameGraphRun run_steady(const MeshView& mesh, const FramePlan& plan) {
    const bool stale = plan.stale;
    auto launch = [&] {
      if (stale || !refit_trees(mesh)) pairs_.reset_counters(exec_);
      run_ops(plan);
    };
    // A probing frame launches plain: probes come in short runs before an update, too few
    // to repay a recording (FrontMaintenance::observe).
    if (!config_.cuda_graph || plan.probe) {
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

  // (5), first half: candidates described from the refitted T_D, its self fronts
  // classified against the old node ranges, then the candidate subtrees rebuilt. The front
  // pass that follows (run_ops) may be re-run on overflow; this part must not be.
  void restructure_tree_and_classify_fronts(Candidates restructuring) {
    timer_.start(Phase::restructure);
    describe_candidates(exec_, bvh_, restructure_, restructuring.count);
    self_.classify(exec_, restructure_.view());
    restructure_subtrees(exec_, bvh_, restructure_, restructuring.count, restructuring.leaves);
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
                                             float(config_.restructure_quality * planner_.q_ref()),
                                             config_.restructure_min_leaves, max_leaves,
                                             restructure_.max_candidates, restructure_.node.data(),
                                             &pairs_.device()->inspect});
    timer_.stop(Phase::inspect);
  }

  bool histogram_sorted() const { return strategy().ordered && !strategy().radix_sort; }

  // Whether the front an operation produces is sorted (--order-updates off: not an update's
  // with the histogram sort), and whether it is counted per tree node: for the sort, or for
  // the balance and inspection that read the counts of a front kept as produced.
  bool sorts(FrontOp op) const {
    return strategy().ordered && (op != FrontOp::update || config_.order_updates || strategy().radix_sort);
  }
  bool counts(FrontOp op) const {
    return histogram_sorted() && (sorts(op) || strategy().balance || strategy().restructure);
  }
  // Whether an update in place keeps the front's count log: for the inspection, which reads
  // it (balance does not run on fronts updated in place: FramePlanner::plan).
  bool counts_in_place() const { return histogram_sorted() && strategy().restructure; }

  // Whether a launch over `fronts` front nodes shares its traversals within warps, as
  // --preserve-warp or --update-warp (`choice`) says (WarpSharing).
  bool shares_in_warp(WarpSharing choice, uint64_t fronts) const {
    return choice == WarpSharing::on ||
           (choice == WarpSharing::automatic && fronts <= kWarpSharingWaves * exec_.resident_threads());
  }

  static Phase phase_of(FrontOp op) {
    return op == FrontOp::generate      ? Phase::generate
           : op == FrontOp::preserve    ? Phase::preserve
           : op == FrontOp::restructure ? Phase::restructure
                                        : Phase::update;
  }

  // Every active query's operation, then the ordering of the fronts they produced.
  void run_ops(const FramePlan& plan) {
    const bool histogram = histogram_sorted();
    bool produced = false;
    for (Query q : kQueries) {
      FrontQuery<Exec>& fq = query(q);
      const FrontOp op = op_of(plan, q);
      if (!fq.active()) continue;
      timer_.start(phase_of(op));
      switch (op) {
        case FrontOp::preserve:
          fq.preserve(exec_, pairs_, stage_preserve_, warp_preserve_, plan.probe);
          break;
        case FrontOp::generate:
          fq.generate(exec_, pairs_, histogram, shares_in_warp(config_.update_warp, fq.query_leaves()));
          break;
        case FrontOp::update:
          if (plan.in_place)
            fq.patch(exec_, pairs_, shares_in_warp(config_.update_warp, fq.total()), counts_in_place(),
                     histogram_sorted());
          else
            fq.update(exec_, pairs_, counts(op), shares_in_warp(config_.update_warp, fq.total()));
          break;
        case FrontOp::restructure:
          fq.restructure(exec_, pairs_, histogram, restructure_.view(), shares_in_warp(config_.update_warp, fq.total()));
          break;
      }
      timer_.stop(phase_of(op));
      produced = produced || produces(plan, q);
    }
    if (plan.in_place && histogram) {
      timer_.start(Phase::front_order);
      for (Query q : kQueries)
        if (patches(plan, q)) query(q).sort_tails(exec_, pairs_);
      if (plan.inspect && patches(plan, Query::self)) self_.offsets(exec_);
      timer_.stop(Phase::front_order);
    }
    if (!strategy().ordered || !produced) return;
    if (strategy().radix_sort) {
      // The sort needs the produced sizes on the host: one more read-back on these frames.
      const FrontCounters& c = pairs_.read_counters(exec_);
      timer_.start(Phase::front_order);
      for (Query q : kQueries)
        if (produces(plan, q)) query(q).radix_order(exec_, radix_, c);
      timer_.stop(Phase::front_order);
      return;
    }
    bool any = false;
    for (Query q : kQueries) any = any || (produces(plan, q) && counts(op_of(plan, q)));
    if (!any) return;
    timer_.start(Phase::front_order);
    for (Query q : kQueries) {
      const FrontOp op = op_of(plan, q);
      if (!produces(plan, q)) continue;
      if (sorts(op))
        query(q).order(exec_, pairs_);
      else if (counts(op))
        query(q).offsets(exec_);
    }
    timer_.stop(Phase::front_order);
  }

  // Preserve stages its pairs per block while blocks produce enough of them to pay for the
  // stage's flush (core/append_stage.h): at least kStagedPairsPerBlock per block of front
  // nodes in the frame just read back (docs/design.md "Constants and their measurements"). A change
  // is a different launch, so the steady frame's graph is recorded again.
  // The traversals are shared within warps as --preserve-warp says (WarpSharing).
  static constexpr uint64_t kStagedPairsPerBlock = 32;
  void choose_preserve_launch(uint64_t pairs) {
    const uint64_t fronts = self_.total() + inter_.total() + rigid_self_.total();
    const bool stage = pairs * kStagedThreads >= kStagedPairsPerBlock * fronts;
    const bool warp = shares_in_warp(config_.preserve_warp, fronts);
    if (stage != stage_preserve_ || warp != warp_preserve_) ++graph_version_;
    stage_preserve_ = stage;
    warp_preserve_ = warp;
  }

  // After a probing frame's read-back, outside its timing: the preserving queries' buffers
  // grow to what an update of their fronts can produce, so the update runs once.
  void reserve_for_update(const FramePlan& plan, const FrontCounters& c) {
    bool grew = false;
    for (Query q : kQueries)
      if (op_of(plan, q) == FrontOp::preserve) grew = query(q).reserve_for_update(exec_, c) || grew;
    if (grew) ++graph_version_;
  }

  // (4) Balance, before each update: the fronts' content is unchanged.
  void balance(const FramePlan& plan) {
    bool any = false;
    for (Query q : kQueries) any = any || (op_of(plan, q) == FrontOp::update && query(q).active());
    if (!any) return;
    timer_.start(Phase::balance);
    for (Query q : kQueries)
      if (op_of(plan, q) == FrontOp::update)
        query(q).balance(exec_, strategy().radix_sort ? &radix_ : nullptr);
    timer_.stop(Phase::balance);
  }

  PipelineConfig config_;
  FramePlanner planner_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  Lbvh<Exec> bvh_;        // T_D: the deformable faces, or every face of an unsplit scene
  Lbvh<Exec> rigid_bvh_;  // T_R: the rigid faces (empty unless a query needs them)
  PairBuffer<Exec, FrontCounters> pairs_;
  RadixScratch<Exec> radix_;
  RestructureScratch<Exec> restructure_;
  FrontQuery<Exec> self_;        // T_D's leaves against T_D
  FrontQuery<Exec> inter_;       // T_D's leaves against T_R
  FrontQuery<Exec> rigid_self_;  // T_R's leaves against T_R
  typename Exec::FrameGraph graph_;  // the steady frame's recording (--cuda-graph)
  uint64_t graph_version_ = 0;       // changes whenever fronts or buffers may have
  bool stage_preserve_ = true;  // preserve's pairs staged per block (choose_preserve_launch)
  bool warp_preserve_ = true;   // preserve's traversals shared within warps (choose_preserve_launch)
};

}  // namespace cdb
