#pragma once
// Front-based pipelines (paper Fig. 4, §5.2): the executor of the frame plans that
// FramePlanner (pipeline/frame_plan.h) decides. Each frame: refit (or rebuild), then one
// front operation per query — (1) generate, (2) preserve, (3) update, with (4) balance
// before it in pipelines b and c, or (5) restructure in c. Produced fronts are ordered by
// histogram sort unless the strategy is `unordered`. One read-back a frame: pair, front and
// inspection counters together; an overflow grows the buffer (counted, listed after the
// run) and re-runs the operation from the untouched current front. The steady frame (refit
// + preserve) replays a CUDA graph while nothing it launches changed: the pair buffer and
// each query count their own changes (revision()), and the recording is keyed by them. With --order-updates
// off an update's front is kept as produced (counted per node where balance or inspection
// reads the counts) and only generated and restructured fronts are sorted. With
// --update-in-place an update writes into the current fronts (holes and an appended tail)
// until their order has decayed by --compact-share; a re-run after an overflow preserves
// such fronts, or generates one whose appends did not fit.
//
// A scene with declared queries and objects for a second tree is split
// (geometry/object_split.h): T_D follows this state machine; T_R over the rigid faces (and
// deformable ones only an inter with T_D names) is built on the first frame and only
// refitted after (rigid motion keeps a tree's quality), or rebuilt with T_D where it holds
// deformable faces. Up to
// three front queries run each frame, each only when a declared query needs it: the self
// fronts of T_D, the cross fronts of T_D's leaves against T_R, and the self fronts of T_R.
// Unsplit, T_D holds every face and only its self fronts run.
//
// --rebuild-ahead: a rebuild after the first frame runs off the frames' critical path. The
// frame that would rebuild refits and preserves instead (a front preserved on the refitted
// tree stays exact however stale, front/front.h), and computes the faces' boxes into a
// second tree; the rest of that tree's build, its self fronts' generate and their ordering
// run on the executor's side stream (lowest priority: exec/cuda_exec.cuh), beside this
// frame and the next ones, which preserve. The side forks after the boxes but is queued
// after the frame's front pass, so its host launches overlap the frame's device work. The
// first frame to find the side's work done adopts it: the second tree and its fronts swap
// with the current ones, then it refits and preserves them. The side's pairs are dropped
// (the frames' own preserves report each frame's pairs), its fronts are checked against
// their buffers at the adoption (a front that outgrew them is generated again there, in
// the frame). It needs what a plain build frame would not read back: the histogram sort or
// no ordering, no second tree (T_R's refit would race the cross fronts' generate), and
// --refit-every 1.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cdbench/front/quality.h"
#include "cdbench/pipeline/frame_plan.h"
#include "cdbench/pipeline/front_counters.h"
#include "cdbench/pipeline/front_query.h"
#include "cdbench/pipeline/pair_pipeline.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

template <class Exec, class Timer>
class FrontPipeline final : public PairPipeline<Exec, Timer, FrontCounters> {
  using Base = PairPipeline<Exec, Timer, FrontCounters>;
  using Base::config_, Base::exec_, Base::timer_, Base::mesh_, Base::pairs_, Base::timed;

 public:
  using Base::run_frame;
  FrontPipeline(const PipelineConfig& config, FrontStrategy chosen)
      : Base(config), planner_(chosen, config), bvh_(exec_), rigid_bvh_(exec_, "rigid_bvh"), restructure_(exec_),
        queries_{{{exec_, "front", Query::self}, {exec_, "inter_front", Query::inter},
                  {exec_, "rigid_front", Query::rigid_self}}},
        ahead_bvh_(exec_, "ahead_bvh"), ahead_front_(exec_, "ahead_front", Query::self), ahead_pairs_(exec_, "ahead_") {
    radix_.bind(exec_.memory());
    if (strategy().restructure) check_restructure_config(config_);
  }

  void set_topology(const Topology& topology) override {
    // A build ahead of the last run that was never adopted still writes the second tree and
    // fronts, which this run reserves again: waited for and dropped.
    exec_.drop_side();
    ahead_due_ = false;
    fresh_ = {};
    if (lent_) exchange_lent();  // a build ahead dropped unadopted returns what it borrowed
    this->set_mesh(topology, true);
    const ObjectSplit& split = mesh_.split();
    bvh_.refit_top_max_leaves = rigid_bvh_.refit_top_max_leaves = config_.tree.refit_top_leaves;
    bvh_.refit_levels = rigid_bvh_.refit_levels = switched_on(config_.tree.refit_levels, Exec::is_device);
    bvh_.reserve(exec_, mesh_.deformable().count);
    rigid_bvh_.reserve(exec_, mesh_.rigid().count);
    const FrontSizing sizing{.per_triangle = config_.capacity.front_per_triangle,
                             .in_place = config_.fronts.update_in_place,
                             .probed = config_.fronts.update_probe};
    query(Query::self).plan(bvh_, bvh_, split.deformable_self, sizing);
    query(Query::inter).plan(bvh_, rigid_bvh_, split.cross, sizing);
    query(Query::rigid_self).plan(rigid_bvh_, rigid_bvh_, split.rigid_self, sizing);
    size_t capacity = 0;
    for (const auto& fq : queries_) capacity = std::max(capacity, fq.capacity());
    if (strategy().radix_sort) radix_.reserve(exec_, capacity);
    if (strategy().restructure) restructure_.reserve(bvh_.num_leaves, config_.restructure.min_leaves);
    builds_ahead_ = can_build_ahead();
    if (builds_ahead_) plan_ahead(sizing);
    planner_.reset(running_queries(), exec_.resident_threads(), builds_ahead_);
    preserve_launch_ = {};
    exec_.sync();
  }

  bool replay_plan(std::shared_ptr<const RecordedPlan> plan) override {
    planner_.replay(std::move(plan));
    return true;
  }

  // Plan, run, read back, adopt; a frame whose buffers had to grow runs its front pass again.
  FrameStats run_frame(const FrameVertices& vertices) override {
    FrameStats stats;
    pairs_.reserve_ahead();
    const FramePlan plan =
        planner_.plan(bvh_.num_leaves, front_nodes(), disorder(), planner_.ahead_in_flight() && exec_.side_done());
    if (plan.ahead) reserve_ahead(plan.ahead_update);
    const size_t allocations = exec_.memory().stats().allocations;
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    const double ahead_ms = plan.adopt ? adopt_ahead(plan.ahead_update) : -1.0;
    const uint64_t fronts = front_nodes();
    // The first frame's generate is timed, phases on or off, where maintenances may
    // generate: what a generate costs bounds a maintenance generate before one ran
    // (FrontMaintenance::generate_due). The first frame is left out of every summary.
    const bool time_generate = planner_.frame() == 0 && planner_.maintenance().regenerates();
    timer_.force_phases(time_generate);
    stats.op = prepare_trees(mesh, plan);
    FramePlan run = plan;  // on a re-run: each query's fronts as they stand
    double first_pass_ms = -1.0;
    for (bool first = true;; first = false) {
      if (first && plan.steady()) {
        stats.timing.graph = frame_graph_run_name(run_steady(mesh, plan));
      } else {
        pairs_.reset_counters(exec_);
        run_ops(run);
      }
      if (run.inspect) inspect_quality();
      timer_.stop_frame();
      if (first) stats.timing.allocations = uint32_t(exec_.memory().stats().allocations - allocations);
      queue_ahead(plan.ahead_update);
      if (adopt(run, pairs_.read_counters(exec_))) break;
      if (first) first_pass_ms = timer_.frame_ms() - timer_.phase_ms(Phase::upload);
      ++stats.timing.query_reruns;
    }
    timer_.force_phases(false);
    describe(plan, stats);
    if (plan.rebuild || (plan.adopt && !plan.ahead_update)) note_fresh_fronts(stats.pairs);
    stats.timing.ahead_ms = std::max(ahead_ms, 0.0);
    const double generate_per_node = time_generate ? price_generate(stats) : -1.0;
    planner_.finish(plan, {.ms = stats.timing.total_ms,
                           .ran_once = stats.timing.query_reruns == 0,
                           .front_nodes = fronts,
                           .q_root = stats.quality.q_root,
                           .found = found(plan),
                           .recorded = stats.timing.graph == "captured",
                           .generate_per_node_ms = generate_per_node,
                           .pairs = stats.pairs,
                           .update_yield = stats.fronts.update_yield,
                           .first_pass_ms = first_pass_ms,
                           .ahead_ms = ahead_ms});
    if (plan.probe) stats.fronts.rebuild_growth = planner_.probed_growth();
    if (run.probe) reserve_for_update(run, pairs_.last_counters());
    choose_preserve_launch(stats.pairs);
    return stats;
  }

 private:
  FrontQuery<Exec>& query(Query q) { return queries_[size_t(q)]; }
  FrontQuery<Exec>& self() { return query(Query::self); }
  const FrontQuery<Exec>& self() const { return queries_[size_t(Query::self)]; }
  const FrontStrategy& strategy() const { return planner_.strategy(); }

  // A probing frame: the front nodes an update of every query's fronts would make at most.
  uint64_t update_yield(const FramePlan& plan) const {
    uint64_t n = 0;
    if (plan.probe)
      for (const auto& fq : queries_) n += fq.update_yield(pairs_.last_counters());
    return n;
  }

  QuerySet running_queries() const {
    QuerySet running{};
    for (Query q : kQueries) running[size_t(q)] = queries_[size_t(q)].active();
    return running;
  }

  uint64_t front_nodes() const {
    uint64_t n = 0;
    for (const auto& fq : queries_) n += fq.total();
    return n;
  }
  // How far updates in place have decayed the fronts' order: the most of any query.
  double disorder() const {
    double d = 0.0;
    for (const auto& fq : queries_) d = std::max(d, fq.disorder());
    return d;
  }
  // Changes whenever anything a recorded steady frame launches may have: the pair buffer
  // or a query's fronts (each counts its own changes).
  uint64_t launch_revision() const {
    uint64_t r = pairs_.revision();
    for (const auto& fq : queries_) r += fq.revision();
    return r;
  }

  // The trees' upkeep and the work that must not be re-run with the front pass: balance
  // before updates, the restructure of T_D. Returns the frame's op (hierarchy + self front).
  std::string prepare_trees(const MeshView& mesh, const FramePlan& plan) {
    if (plan.ahead) plan.ahead_update ? update_ahead() : build_ahead(mesh);
    const std::string op = plan.stale    ? "stale"
                           : plan.ahead  ? (plan.ahead_update ? "refit-update-ahead" : "refit-ahead")
                           : plan.adopt  ? (plan.ahead_update ? "adopt-update" : "adopt")
                           : plan.steady() ? "refit"
                                           : update_trees(mesh, plan.rebuild);
    if (plan.balance) balance(plan);
    if (plan.op(Query::self) == FrontOp::restructure) restructure_tree_and_classify_fronts(plan.restructuring);
    return op + "+" + (plan.patches(Query::self) ? "update-in-place" : front_op_name(plan.op(Query::self)));
  }

  // Refit or rebuild T_D; T_R is built on the first frame and refitted after, or rebuilt
  // with T_D where it holds deformable objects (every front is generated then).
  std::string update_trees(const MeshView& mesh, bool rebuild) {
    const std::string op = update_hierarchy(exec_, timer_, bvh_, mesh, mesh_.deformable(), rebuild,
                                            config_.tree.morton_bits, strategy().radix_sort, nullptr,
                                            mesh_.pieces());
    update_hierarchy(exec_, timer_, rigid_bvh_, mesh, mesh_.rigid(),
                     mesh_.split().rigid_tree_builds(planner_.frame() == 0, rebuild), config_.tree.morton_bits,
                     strategy().radix_sort, mesh_.face_object());
    return op;
  }

  // After the read-back (`c`): the produced fronts become current and true; or, where a
  // buffer had to grow, false, and `run` says what the re-run does. Fronts updated in place
  // are current already: a re-run preserves them, or generates one whose appends did not
  // fit. Other queries re-run their operation from the untouched current fronts.
  bool adopt(FramePlan& run, const FrontCounters& c) {
    bool again = pairs_.grow_if_needed();
    for (Query q : kQueries) {
      if (!run.patches(q)) continue;
      const bool kept = query(q).adopt_patch(exec_, c);
      run.op(q) = kept ? FrontOp::preserve : FrontOp::generate;
      again = again || !kept;
    }
    for (Query q : kQueries)
      if (run.op(q) != FrontOp::preserve) again = query(q).grow_if_needed(exec_, c) || again;
    if (again) return false;
    for (Query q : kQueries)
      if (run.op(q) != FrontOp::preserve) query(q).adopt(exec_, c, sorts(run.op(q)));
    return true;
  }

  // The frame's counts, fronts and timings for its stats, after its last read-back.
  void describe(const FramePlan& plan, FrameStats& stats) const {
    stats.pairs = pairs_.count();
    stats.quality.decision = formula2_name(plan.decision);
    stats.plan = planner_.step(plan);
    stats.fronts.internal = self().live(kInternalFront);
    stats.fronts.external = self().live(kExternalFront);
    stats.fronts.inter = queries_[size_t(Query::inter)].live_total();
    stats.fronts.rigid = queries_[size_t(Query::rigid_self)].live_total();
    stats.fronts.disorder = disorder();
    stats.fronts.update_yield = update_yield(plan);
    stats.quality.q_root = strategy().ordered && stats.fronts.external
                       ? double(stats.fronts.internal) / double(stats.fronts.external)
                       : 0.0;
    if (plan.inspect) {
      const InspectCounters& c = pairs_.last_counters().inspect;
      stats.quality.candidates = c.candidates;
      stats.quality.candidate_leaves = c.candidate_leaves;
      stats.quality.q_candidates = c.candidates ? double(c.candidate_q_milli) / 1000.0 / double(c.candidates) : 0.0;
    }
    record_timings(timer_, stats);
  }

  // What this frame's inspection found, capped at the candidates' buffer.
  Candidates found(const FramePlan& plan) const {
    if (!plan.inspect) return {};
    const InspectCounters& c = pairs_.last_counters().inspect;
    return {uint32_t(std::min<unsigned long long>(c.candidates, restructure_.max_candidates)),
            uint32_t(c.candidate_leaves), uint64_t(c.candidate_front_nodes)};
  }

  // The build frame's generate and its ordering, per front node produced (a re-run after a
  // buffer grew ran them again); the phases are then cleared unless phases are timed.
  double price_generate(FrameStats& stats) const {
    double& gen = stats.timing.phase_ms[size_t(Phase::generate)];
    double& order = stats.timing.phase_ms[size_t(Phase::front_order)];
    const uint64_t produced = stats.fronts.internal + stats.fronts.external + stats.fronts.inter + stats.fronts.rigid;
    const double per_node = (gen + order) / double(1 + stats.timing.query_reruns) / double(std::max<uint64_t>(produced, 1));
    if (!config_.launch.phase_timing) gen = order = 0.0;
    return per_node;
  }

  // A steady frame's refit of both trees; T_D's zeroes the pair buffer's counters on its
  // way, which saves the frame a launch. True if it did.
  bool refit_trees(const MeshView& mesh) {
    bool zeroed = false;
    timed(Phase::refit, [&] {
      zeroed = refit(exec_, bvh_, mesh, pairs_.counter_reset());
      refit(exec_, rigid_bvh_, mesh);
    });
    return zeroed;
  }

  // A steady frame's work (refit unless stale, counters, preserve), through the frame graph
  // with --cuda-graph. The key holds what the launches depend on: launch_revision(), the
  // vertex buffers (swept boxes alternate them), whether the frame refits, and the
  // preserve's launch choices.
  FrameGraphRun run_steady(const MeshView& mesh, const FramePlan& plan) {
    auto launch = [&] {
      if (plan.stale || !refit_trees(mesh)) pairs_.reset_counters(exec_);
      run_ops(plan);
    };
    // A probing frame launches plain: probes come in short runs before an update, too few
    // to repay a recording (FrontMaintenance::observe).
    if (!config_.launch.cuda_graph || plan.probe) {
      launch();
      return FrameGraphRun::plain;
    }
    const PreserveLaunch& preserve = preserve_launch_;
    const uint64_t choices = uint64_t(plan.stale) | uint64_t(preserve.staged) << 1 |
                             uint64_t(preserve.share_in_warp) << 2 |
                             uint64_t(preserve.occupancy == Occupancy::bounded) << 3 |
                             uint64_t(preserve.two_nodes) << 4;
    const FrameGraphKey key{launch_revision(), uint64_t(reinterpret_cast<uintptr_t>(mesh.vertices)),
                            uint64_t(reinterpret_cast<uintptr_t>(mesh.prev_vertices)), choices};
    return graph_.run(exec_, timer_, key, launch);
  }

  static void check_restructure_config(const PipelineConfig& c) {
    if (c.restructure.min_leaves < 2) fail("--restructure-min-leaves must be at least 2");
    if (!(c.restructure.max_fraction > 0.0 && c.restructure.max_fraction <= 1.0))
      fail("--restructure-max-fraction must be in (0, 1]");
    if (!(c.restructure.quality >= 0.0)) fail("--restructure-quality must be at least 0");
    if (!(c.restructure.threshold_refit >= 0.0) || !(c.restructure.threshold_build >= c.restructure.threshold_refit))
      fail("thresholds must satisfy 0 <= --threshold-refit <= --threshold-build");
  }

  // (5), first half: candidates described from the refitted T_D, its self fronts
  // classified against the old node ranges, then the candidate subtrees rebuilt. The front
  // pass that follows (run_ops) may be re-run on overflow; this part must not be.
  void restructure_tree_and_classify_fronts(Candidates restructuring) {
    timed(Phase::restructure, [&] {
      describe_candidates(exec_, bvh_, restructure_, restructuring.count);
      self().classify(exec_, restructure_.view());
      restructure_subtrees(exec_, bvh_, restructure_, restructuring.count, restructuring.leaves);
    });
  }

  // Whether rebuilds are built ahead (--rebuild-ahead; auto: on the GPU): where nothing the
  // side stream runs needs a read-back or races the frames (see the top of this file).
  bool can_build_ahead() const {
    return switched_on(config_.tree.rebuild_ahead, Exec::is_device) && !strategy().rebuild_every_frame &&
           !strategy().radix_sort && config_.tree.refit_every == 1 && self().active() &&
           !queries_[size_t(Query::inter)].active() && !queries_[size_t(Query::rigid_self)].active();
  }

  // The side stream and the settings of the second tree and its self fronts (active: a
  // build runs ahead only where T_D's self fronts do, can_build_ahead); its pairs are
  // counted, not kept. The tree, fronts and counters themselves are reserved by the run's
  // first build ahead (reserve_ahead_tree): a run that never builds ahead, as the cloth
  // waves, holds none of them (about 280 bytes a leaf).
  void plan_ahead(FrontSizing sizing) {
    ahead_bvh_.refit_top_max_leaves = bvh_.refit_top_max_leaves;
    ahead_bvh_.refit_levels = bvh_.refit_levels;
    ahead_bvh_.build_scratch = BuildScratch::lent;
    sizing.produced = places_ahead() ? ProducedArrays::lent_as_current : ProducedArrays::lent;
    ahead_sizing_ = sizing;
    ahead_reserved_ = ahead_fronts_reserved_ = false;
    exec_.reserve_side();
  }

  // The second tree and its self fronts, sized as the current ones; neither holds what the
  // current ones lend it for each build ahead (build_ahead): the tree's build scratch and
  // the fronts' produced arrays. Once a run (the first build ahead; counted growths).
  void reserve_ahead_tree() {
    if (ahead_reserved_) return;
    ahead_bvh_.reserve(exec_, bvh_.num_leaves);
    reserve_ahead_fronts();
    ahead_reserved_ = true;
  }

  // What an update ahead needs of them (update_ahead): the second tree's boxes, for the copy
  // of T_D's, and the second self fronts. Once a run (the first update or build ahead).
  void reserve_ahead_fronts() {
    if (ahead_fronts_reserved_) return;
    ahead_bvh_.reserve_boxes(bvh_.num_leaves);
    ahead_front_.plan(ahead_bvh_, ahead_bvh_, true, ahead_sizing_);
    ahead_pairs_.reserve(0);
    ahead_fronts_reserved_ = true;
  }

  // What a fork lends and the room it needs: T_D's build scratch and its self fronts'
  // produced arrays lent to the second tree and fronts, reserved once a run, with room for
  // what a build is expected to generate (build_expected) or for the current fronts and what
  // their probe sized them to (an update), and a spare. Left lent: the forking frame's work
  // runs on them.
  void lend_ahead(bool update) {
    if (update)
      reserve_ahead_fronts();
    else
      reserve_ahead_tree();
    const std::array<size_t, 2> capacity = {self().front(kInternalFront).capacity(),
                                            self().front(kExternalFront).capacity()};
    const std::array<size_t, 2> expected =
        update ? std::array<size_t, 2>{self().size(kInternalFront), self().size(kExternalFront)} : build_expected();
    exchange_lent();
    ahead_front_.reserve_ahead(exec_, expected, update ? capacity : std::array<size_t, 2>{0, 0});
  }

  // The self fronts a build ahead is expected to generate, per kind: fresh fronts on a new
  // tree, so the fronts last generated on one (a build in its frame, or a build ahead at its
  // adoption), scaled by the pairs since where those grew, and at most what the current
  // fronts hold. The current fronts alone are a poor guide once updates on a degrading tree
  // have grown them: n-body's held 7.67M internal nodes when its second build ahead forked,
  // and it generated 2.24M (c on the host, replaying the H100 bar's plan).
  std::array<size_t, 2> build_expected() const {
    std::array<size_t, 2> n = {self().size(kInternalFront), self().size(kExternalFront)};
    if (!fresh_.known) return n;
    const double growth = std::max(1.0, double(pairs_.count()) / double(std::max<uint64_t>(fresh_.pairs, 1)));
    for (int k = 0; k < 2; ++k) n[k] = std::min(n[k], size_t(std::ceil(double(fresh_.nodes[k]) * growth)));
    return n;
  }

  // After a frame that built T_D and generated its self fronts, or adopted a build ahead's:
  // their sizes and the frame's pairs (build_expected).
  void note_fresh_fronts(uint64_t pairs) {
    fresh_ = {.nodes = {self().size(kInternalFront), self().size(kExternalFront)}, .pairs = pairs, .known = true};
  }

  // Before the frame that forks a build or update ahead starts its timing: lend_ahead, then
  // the lending undone, so that the frame's own lend_ahead finds every array sized and the
  // frame allocates nothing. Reserved inside it, the second tree and fronts of a run's first
  // build or update ahead made that frame 5-19x a steady one on the H100 (the avatar's c, its
  // first pass: 3.22 against 0.25 ms; results/2026-12-08-h100/bar), as growths after a
  // read-back are kept out of a frame.
  void reserve_ahead(bool update) {
    lend_ahead(update);
    exchange_lent();
  }

  // The ahead frame's part: the current tree's build scratch and its self fronts' produced
  // arrays lent to the ones built ahead (until it is adopted, T_D only refits and its fronts
  // only preserve: FramePlanner::in_flight), room for the new self fronts (what the current
  // ones hold, and a spare), the faces' boxes on the frame's stream (the build's only read of
  // the mesh, whose buffer the next frame's upload overwrites), then the build, its order,
  // the generate and the fronts' ordering on the side stream.
  void build_ahead(const MeshView& mesh) {
    lend_ahead(false);
    timed(Phase::build, [&] { build_boxes(exec_, ahead_bvh_, mesh, mesh_.deformable()); });
    exec_.mark_side_fork();
    ahead_due_ = true;
  }

  // The side's part of a build ahead, queued once the frame's own front pass is: its 30-odd
  // launches (the build's sorts and scans, the generate, the ordering) queued first would
  // hold the frame's launches back on the host while the frame's stream waits for them.
  // `update`: the side's work is an update ahead (update_ahead), not a build.
  void queue_ahead(bool update) {
    if (!ahead_due_) return;
    ahead_due_ = false;
    if (update) {
      exec_.on_side([&] { update_fronts_ahead(); });
      return;
    }
    exec_.on_side([&] {
      build_from_boxes(exec_, ahead_bvh_, config_.tree.morton_bits, mesh_.deformable(), nullptr, mesh_.pieces());
      order_depth_first(exec_, ahead_bvh_);
      generate_ahead();
    });
  }

  // --ahead-generate place: generated twice, into the arrays the current fronts lend, in
  // order (FrontQuery::generate_placed); scatter: generated into the lent produced arrays,
  // then ordered into the second fronts' own.
  void generate_ahead() {
    ahead_pairs_.reset_counters(exec_);
    const ProduceMode mode{.histogram = histogram_sorted(),
                           .share_in_warp = shares_in_warp(config_.fronts.update_warp, ahead_front_.query_leaves())};
    if (places_ahead()) {
      ahead_front_.generate_placed(exec_, ahead_pairs_, mode);
      return;
    }
    ahead_front_.generate(exec_, ahead_pairs_, mode);
    order_ahead(FrontOp::generate);
  }

  // The second fronts that `op` produced on the side, ordered as the frame's would be
  // (order_produced): sorted, or only counted per tree node, or kept as produced.
  void order_ahead(FrontOp op) {
    if (!sorts(op)) {
      if (counts(op)) ahead_front_.offsets(exec_);
      return;
    }
    FrameFit fit;
    ahead_front_.add_to_fit(fit, ahead_pairs_, false);
    ahead_front_.order(exec_, ahead_pairs_, fit);
  }

  // --update-ahead, the frame that would update: as build_ahead lends (the tree's build
  // scratch, which no build needs meanwhile, and the self fronts' produced arrays, which the
  // update ahead produces into), with room in the second fronts for what the current ones
  // were sized to (their probe), then T_D's boxes copied into the second tree's (the boxes
  // of the frame before: this frame's refit follows), which the side's update reads while
  // the frames' refits rewrite T_D's. The tree's shape is unchanged until the adoption
  // (the frames in flight only refit), so the update reads T_D's own links, and the second
  // tree holds its boxes alone until a build ahead needs the rest.
  void update_ahead() {
    lend_ahead(true);
    timed(Phase::update, [&] {
      exec_.copy(ahead_bvh_.leaf_box.data(), bvh_.leaf_box.data(), bvh_.num_leaves);
      if (bvh_.num_leaves > 1) exec_.copy(ahead_bvh_.node_box.data(), bvh_.node_box.data(), bvh_.num_leaves - 1);
    });
    exec_.mark_side_fork();
    ahead_due_ = true;
  }

  // T_D's links with the second tree's copy of its boxes: what an update ahead traverses.
  FrontView update_ahead_view() const {
    FrontView v = self().view();
    v.tree.bvh.leaf_box = ahead_bvh_.leaf_box.data();
    v.tree.bvh.node_box = ahead_bvh_.node_box.data();
    v.query = ahead_bvh_.leaf_box.data();
    return v;
  }

  // The side's part of an update ahead (or its re-run in the adopting frame): the current
  // self fronts updated into the second fronts, then ordered as an update's are.
  // With --ahead-generate place, updated twice, into the arrays the current fronts lend, in
  // order where updates are sorted (FrontQuery::update_placed_from).
  void update_fronts_ahead() {
    ahead_pairs_.reset_counters(exec_);
    const ProduceMode mode{.histogram = counts(FrontOp::update),
                           .share_in_warp = shares_in_warp(config_.fronts.update_warp, self().total())};
    if (places_ahead()) {
      ahead_front_.update_placed_from(exec_, ahead_pairs_, mode, sorts(FrontOp::update), self(), update_ahead_view());
      return;
    }
    ahead_front_.update_from(exec_, ahead_pairs_, mode, self(), update_ahead_view());
    order_ahead(FrontOp::update);
  }

  // The adopt frame's part, before its refit: waits for the side (done already where the
  // planner decided; a replayed adopt may wait), reads the new fronts' sizes (the frame's
  // second read-back), produces them again in the frame where they outgrew their buffers,
  // then swaps tree and self fronts with the current ones; fronts updated ahead (`update`)
  // swap alone, and the build scratch comes back on its own. Returns the side's milliseconds.
  double adopt_ahead(bool update) {
    const double ms = exec_.finish_side();
    const FrontCounters* c = &ahead_pairs_.read_counters(exec_);
    while (ahead_front_.grow_if_needed(exec_, *c)) {
      if (update)
        timed(Phase::update, [&] { update_fronts_ahead(); });
      else
        timed(Phase::generate, [&] { generate_ahead(); });
      c = &ahead_pairs_.read_counters(exec_);
    }
    ahead_front_.adopt(exec_, *c, sorts(update ? FrontOp::update : FrontOp::generate));
    // What was lent comes back with the tree and fronts built ahead: the swaps leave the
    // second tree and fronts holding none of it again.
    if (update)
      bvh_.swap_build_scratch(ahead_bvh_);
    else
      bvh_.swap(ahead_bvh_);
    self().swap_fronts(ahead_front_);
    if (places_ahead()) self().take_back_produced(exec_, ahead_front_);
    lent_ = false;
    return ms;
  }

  // Lends T_D's build scratch and self fronts' produced arrays to the build ahead, or, lent,
  // takes them back: each exchange undoes the last.
  void exchange_lent() {
    bvh_.swap_build_scratch(ahead_bvh_);
    self().lend_produced(ahead_front_);
    lent_ = !lent_;
  }

  void inspect_quality() {
    const uint32_t n = bvh_.num_leaves;
    if (n < 2) return;
    const uint32_t max_leaves = std::max<uint32_t>(
        config_.restructure.min_leaves, uint32_t(config_.restructure.max_fraction * double(n)));
    timed(Phase::inspect, [&] {
      exec_.for_each_n(n - 1, InspectQualityFn{bvh_.node_first.data(), bvh_.node_last.data(),
                                               bvh_.node_parent.data(), self().front(kInternalFront).offset_log.data(),
                                               self().front(kExternalFront).offset_log.data(),
                                               float(config_.restructure.quality * planner_.q_ref()),
                                               config_.restructure.min_leaves, max_leaves,
                                               restructure_.max_candidates, restructure_.node.data(),
                                               &pairs_.device()->inspect});
    });
  }

  bool histogram_sorted() const { return strategy().ordered && !strategy().radix_sort; }
  // --ahead-generate place: the second fronts are produced in order into the lent arrays.
  bool places_ahead() const { return config_.tree.ahead_placed; }

  // Whether the front an operation produces is sorted (--order-updates off: not an update's
  // with the histogram sort), and whether it is counted per tree node: for the sort, or for
  // the balance and inspection that read the counts of a front kept as produced.
  bool sorts(FrontOp op) const {
    return strategy().ordered && (op != FrontOp::update || config_.fronts.order_updates || strategy().radix_sort);
  }
  bool counts(FrontOp op) const {
    return histogram_sorted() && (sorts(op) || strategy().balance || strategy().restructure);
  }
  // Whether an update in place keeps the front's count log: for the inspection, which reads
  // it (balance does not run on fronts updated in place: FramePlanner::plan).
  bool counts_in_place() const { return histogram_sorted() && strategy().restructure; }

  // Whether a launch over `fronts` front nodes shares its traversals within warps, as
  // --preserve-warp or --update-warp (`choice`) says (AutoSwitch).
  bool shares_in_warp(AutoSwitch choice, uint64_t fronts) const {
    return switched_on(choice, fronts <= kWarpSharingWaves * exec_.resident_threads());
  }

  static Phase phase_of(FrontOp op) {
    return op == FrontOp::generate      ? Phase::generate
           : op == FrontOp::preserve    ? Phase::preserve
           : op == FrontOp::restructure ? Phase::restructure
                                        : Phase::update;
  }

  // One query's operation of the plan.
  void run_op(const FramePlan& plan, Query q) {
    FrontQuery<Exec>& fq = query(q);
    const FrontOp op = plan.op(q);
    const bool histogram = histogram_sorted();
    // Generates share a leaf's traversal out in warps, the other operations a front node's.
    const bool warp_leaves = shares_in_warp(config_.fronts.update_warp, fq.query_leaves());
    const bool warp_fronts = shares_in_warp(config_.fronts.update_warp, fq.total());
    timed(phase_of(op), [&] {
      switch (op) {
        case FrontOp::preserve:
          fq.preserve(exec_, pairs_, preserve_launch_, plan.probe);
          break;
        case FrontOp::generate:
          fq.generate(exec_, pairs_, {.histogram = histogram, .share_in_warp = warp_leaves});
          break;
        case FrontOp::update:
          if (plan.in_place)
            fq.patch(exec_, pairs_,
                     {.share_in_warp = warp_fronts, .counted = counts_in_place(), .sort_tail = histogram});
          else
            fq.update(exec_, pairs_, {.histogram = counts(op), .share_in_warp = warp_fronts});
          break;
        case FrontOp::restructure:
          fq.restructure(exec_, pairs_, {.histogram = histogram, .share_in_warp = warp_fronts}, restructure_.view());
          break;
      }
    });
  }

  // Every active query's operation, then the ordering of the fronts they produced.
  void run_ops(const FramePlan& plan) {
    bool produced = false;
    for (Query q : kQueries) {
      if (!query(q).active()) continue;
      run_op(plan, q);
      produced = produced || plan.produces(q);
    }
    if (plan.in_place && histogram_sorted())
      timed(Phase::front_order, [&] {
        for (Query q : kQueries)
          if (plan.patches(q)) query(q).sort_tails(exec_, pairs_);
        if (plan.inspect && plan.patches(Query::self)) self().offsets(exec_);
      });
    if (strategy().ordered && produced) order_produced(plan);
  }

  // The ordering of the fronts the plan's operations produced: by radix sort, which needs
  // their sizes on the host (one more read-back on these frames), or by histogram. Either
  // writes into the current fronts only where all of the frame's appends fit (FrontArrays).
  void order_produced(const FramePlan& plan) {
    if (strategy().radix_sort) {
      const FrontCounters& c = pairs_.read_counters(exec_);
      bool fits = c.pairs <= pairs_.capacity();
      for (Query q : kQueries)
        if (plan.op(q) != FrontOp::preserve) fits = fits && query(q).fits(c, plan.patches(q));
      timed(Phase::front_order, [&] {
        for (Query q : kQueries)
          if (plan.produces(q)) query(q).radix_order(exec_, radix_, c, fits);
      });
      return;
    }
    bool any = false;
    for (Query q : kQueries) any = any || (plan.produces(q) && counts(plan.op(q)));
    if (!any) return;
    const FrameFit fit = frame_fit(plan);
    timed(Phase::front_order, [&] {
      for (Query q : kQueries) {
        if (!plan.produces(q)) continue;
        if (sorts(plan.op(q)))
          query(q).order(exec_, pairs_, fit);
        else if (counts(plan.op(q)))
          query(q).offsets(exec_);
      }
    });
  }

  // The counts of every append the plan's operations make (pairs, produced fronts, tails of
  // updates in place), against their buffers, for the scatters into current fronts.
  FrameFit frame_fit(const FramePlan& plan) {
    FrameFit fit;
    fit.add(&pairs_.device()->pairs, pairs_.capacity());
    for (Query q : kQueries)
      if (plan.op(q) != FrontOp::preserve) query(q).add_to_fit(fit, pairs_, plan.patches(q));
    return fit;
  }

  // Preserve stages its pairs per block while blocks produce enough of them to pay for the
  // stage's flush (core/append_stage.h): at least kStagedPairsPerBlock per block of
  // front nodes in the frame just read back. The traversals are shared within warps as
  // --preserve-warp says (AutoSwitch), launched under its register bound as
  // --preserve-bound says, and with two front nodes a thread as --preserve-two-nodes says
  // (that launch has no bound). The choices are part of the steady frame's key.
  void choose_preserve_launch(uint64_t pairs) {
    const uint64_t fronts = front_nodes();
    const bool bounded =
        switched_on(config_.fronts.preserve_bound, fronts >= kPreserveBoundedWaves * exec_.resident_threads());
    preserve_launch_ = {.staged = pairs * kStagedThreads >= kStagedPairsPerBlock * fronts,
                        .share_in_warp = shares_in_warp(config_.fronts.preserve_warp, fronts),
                        .occupancy = bounded ? Occupancy::bounded : Occupancy::plain,
                        .two_nodes = switched_on(config_.fronts.preserve_two_nodes,
                                                 Exec::is_device &&
                                                     fronts >= kPreserveTwoNodesWaves * exec_.resident_threads())};
  }

  // After a probing frame, outside its timing, once the planner has judged the probe: the
  // preserving queries' buffers grow to what an update of their fronts can produce, so the
  // update runs once. Not T_D's self fronts where the maintenance probed rebuilds the tree
  // ahead: the build generates its own (FrontQuery::reserve_ahead) and the current ones only
  // preserve until it is adopted. Their bound, grown for an update that never came, was the
  // largest part of the dragon's peak (a probe's bound counts every front node that does not
  // descend once, before the update's pruning merges them: 2.3 times the largest front the
  // host's run made, docs/design.md "Memory").
  void reserve_for_update(const FramePlan& plan, const FrontCounters& c) {
    const bool rebuilt_ahead = planner_.next_maintenance_builds_ahead();
    for (Query q : kQueries)
      if (plan.op(q) == FrontOp::preserve && !(q == Query::self && rebuilt_ahead))
        query(q).reserve_for_update(exec_, c);
  }

  // (4) Balance, before each update: the fronts' content is unchanged.
  void balance(const FramePlan& plan) {
    bool any = false;
    for (Query q : kQueries) any = any || (plan.op(q) == FrontOp::update && query(q).active());
    if (!any) return;
    timed(Phase::balance, [&] {
      for (Query q : kQueries)
        if (plan.op(q) == FrontOp::update) query(q).balance(exec_, strategy().radix_sort ? &radix_ : nullptr);
    });
  }

  FramePlanner planner_;
  Lbvh<Exec> bvh_;        // T_D: the faces the split gives it, or every face of an unsplit scene
  Lbvh<Exec> rigid_bvh_;  // T_R: the rigid faces and the split's deformable ones (empty unless needed)
  RadixScratch<Exec> radix_;
  RestructureScratch<Exec> restructure_;
  // By Query: T_D's leaves against T_D, T_D's leaves against T_R, T_R's against T_R.
  std::array<FrontQuery<Exec>, kQueryCount> queries_;
  typename Exec::FrameGraph graph_;  // the steady frame's recording (--cuda-graph)
  // --rebuild-ahead: the tree built ahead, its self fronts and the counters of their generate.
  bool builds_ahead_ = false;
  bool ahead_due_ = false;  // build_ahead() or update_ahead() ran this frame; queue_ahead() queues the side's part
  bool lent_ = false;       // the build ahead holds T_D's build scratch and self fronts' produced arrays
  // The self fronts last generated on a new tree, and the pairs of the frame that built or
  // adopted them (note_fresh_fronts): what a build ahead's fronts are sized from
  // (build_expected).
  struct FreshFronts {
    std::array<size_t, 2> nodes{};
    uint64_t pairs = 0;
    bool known = false;
  } fresh_;
  bool ahead_reserved_ = false;  // this run reserved the second tree and fronts (reserve_ahead_tree)
  bool ahead_fronts_reserved_ = false;  // ... its boxes and the second fronts (reserve_ahead_fronts)
  FrontSizing ahead_sizing_;
  Lbvh<Exec> ahead_bvh_;
  FrontQuery<Exec> ahead_front_;
  PairBuffer<Exec, FrontCounters> ahead_pairs_;
  PreserveLaunch preserve_launch_;  // choose_preserve_launch's, from the frame before
};

}  // namespace cdb
