#pragma once
// The front pipelines' per-frame decision (paper Fig. 4, §4.2, §5.2), apart from the kernels
// that carry it out (pipeline/front_pipeline.h): build or refit the hierarchy, and which front
// operation each query runs: (1) generate, (2) preserve, (3) update, with (4) balance before
// it in pipelines b and c, or (5) restructure in c. Pure host logic over the frame counter,
// the strategy, the measured frame costs (pipeline/front_maintenance.h) and, in c, what the
// last quality inspection found; or a recorded plan, replayed frame by frame
// (pipeline/plan_record.h), so that passes, runs and binaries run the same operations.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>

#include "cdbench/core/error.h"
#include "cdbench/pipeline/front_counters.h"
#include "cdbench/pipeline/front_maintenance.h"
#include "cdbench/pipeline/maintenance_choice.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/plan_record.h"
#include "cdbench/pipeline/restructure_price.h"
#include "cdbench/pipeline/tree_maintenance.h"

namespace cdb {

// The paper's strategies (§5.2, Fig. 5) as choices of one front pipeline.
struct FrontStrategy {
  bool ordered = true;             // histogram-sort fronts after producing them
  bool balance = false;            // (4) before every (3)
  bool periodic = false;           // (1) instead of (3) every second maintenance
  bool rebuild_every_frame = false;  // the reference strategy
  bool radix_sort = false;  // order fronts and BVH with a radix sort instead of the histogram (Fig. 6 baseline)
  bool restructure = false;  // pipeline c: inspect quality, Formula 2, (5) restructure
  // Two names with equal strategies are one pipeline (static = b, restructure = c).
  bool operator==(const FrontStrategy&) const = default;
};

// Degraded subtrees found by pipeline c's inspection: how many, and their leaves.
struct Candidates {
  uint32_t count = 0, leaves = 0;
  uint64_t front_nodes = 0;  // the front nodes in them (InspectCounters)
};

// One frame of a front pipeline.
struct FramePlan {
  bool rebuild = false;  // build the trees (else refit them)
  bool stale = false;    // --refit-every: keep the last boxes, refit nothing
  // --rebuild-ahead: the frame refits and preserves, and a new T_D and its self fronts are
  // built on the executor's side stream (ahead); or the frame first replaces T_D and its self
  // fronts with those built ahead, then refits and preserves (adopt).
  bool ahead = false;
  bool adopt = false;
  // --update-ahead: what runs on the side (ahead) or is adopted (adopt) is an update of
  // T_D's self fronts on the current tree, not a new tree: adopting replaces the fronts only.
  bool ahead_update = false;
  // Each front query's operation, by Query (pipeline/front_counters.h).
  std::array<FrontOp, kQueryCount> ops = {FrontOp::preserve, FrontOp::preserve, FrontOp::preserve};
  // The updates write into the current fronts (FrontConfig::update_in_place), not whole
  // new ones.
  bool in_place = false;
  bool balance = false;  // (4) before the updates
  bool inspect = false;  // pipeline c: inspect T_D's quality after the update
  // Preserving queries count what an update of their fronts would produce (an update is
  // near: FrontMaintenance::update_near), and their buffers grow to it after the frame.
  bool probe = false;
  Formula2 decision = Formula2::none;
  Candidates restructuring;  // what (5) restructures this frame

  FrontOp op(Query q) const { return ops[size_t(q)]; }
  FrontOp& op(Query q) { return ops[size_t(q)]; }
  // Whether query q updates its fronts in place (PatchFrontFn), or produces new ones.
  bool patches(Query q) const { return in_place && op(q) == FrontOp::update; }
  bool produces(Query q) const { return op(q) != FrontOp::preserve && !patches(q); }
  bool updates() const {
    return std::find(ops.begin(), ops.end(), FrontOp::update) != ops.end();
  }
  // Whether any query changes its fronts (anything but preserve).
  bool changes_fronts() const {
    return std::find_if(ops.begin(), ops.end(), [](FrontOp o) { return o != FrontOp::preserve; }) != ops.end();
  }
  bool steady() const { return !rebuild && !changes_fronts(); }
};

class FramePlanner {
 public:
  FramePlanner(FrontStrategy strategy, const PipelineConfig& config)
      : strategy_(strategy),
        config_(config),
        maintenance_(config.fronts.cycle, config.fronts.regenerate),
        tree_(config.tree.rebuild_degraded && maintenance_.adaptive() && !strategy.rebuild_every_frame),
        price_(config.restructure.priced) {}

  const FrontStrategy& strategy() const { return strategy_; }
  const FrontMaintenance& maintenance() const { return maintenance_; }
  // The last probe's count of an update over a rebuild (TreeMaintenance::probed_growth).
  double probed_growth() const { return tree_.probed_growth(); }
  // The growth past which a maintenance rebuilds (TreeMaintenance, --rebuild-growth).
  double rebuild_growth() const { return tree_.rebuild_growth(); }
  // After a probing frame's finish(): whether the maintenance probed for rebuilds the tree
  // ahead instead of updating the fronts. A replayed plan says so in its next step; a
  // decided one rebuilds where the probe found the tree degraded (decided(): the next
  // maintenance follows this probe, and an unprobed one waits for another).
  bool next_maintenance_builds_ahead() const {
    if (!builds_ahead_) return false;
    if (replay_) return frame_ < replay_->frames.size() && replay_->frames[frame_].step.trees == TreeStep::ahead;
    return tree_.rebuild_due();
  }
  const RestructurePrice& restructure_price() const { return price_; }

  // A new run over the frames: the first frame builds. `running`: the queries that run in
  // the scene, which a replayed plan must give operations to, and only those; `wave`: the
  // device's resident threads (TreeMaintenance).
  // `builds_ahead`: a rebuild after the first frame is built ahead (--rebuild-ahead, where
  // the pipeline can: FrontPipeline).
  void reset(const QuerySet& running = {true, true, true}, uint64_t wave = 1, bool builds_ahead = false) {
    frame_ = generated_ = produced_ = maintained_ = 0;
    probed_ = in_flight_ = in_flight_update_ = false;
    pending_ = {};
    q_ref_ = 0.0;
    maintenance_.reset();
    choice_.reset();
    tree_.reset(wave, config_.tree.rebuild_growth);
    price_.reset();
    running_ = running;
    builds_ahead_ = builds_ahead;
    if (replay_) {
      check_plan_queries(*replay_, running_);
      check_plan_steps(*replay_, target(builds_ahead_));
    }
  }
  bool builds_ahead() const { return builds_ahead_; }
  // --update-ahead: due updates of T_D's self fronts run on the side stream (reset).
  bool updates_ahead() const { return builds_ahead_ && switched_on(config_.fronts.update_ahead, true); }
  // --maintain-ahead: the next maintenance after the first frame is a rebuild built ahead
  // (on: every one; auto: where the last cycle begun so cost less, MaintenanceChoice).
  bool maintains_ahead() const {
    return builds_ahead_ && frame_ > 0 && switched_on(config_.tree.maintain_ahead, choice_.ahead_due());
  }
  const MaintenanceChoice& maintenance_choice() const { return choice_; }

  // Before a run (reset): each frame runs the recorded step of `plan` instead of deciding
  // one; nullptr decides again. The plan forces the trees' build, refit or stale boxes,
  // each query's operation, the Formula 2 decision reported and the inspections; a
  // restructure restructures what the replay's own inspection on the frame before found.
  // In-place updates, balance and probes follow the configuration, as when deciding.
  // Throws Error naming the plan's frame when a step cannot run on this strategy.
  void replay(std::shared_ptr<const RecordedPlan> plan) {
    if (plan) check_plan_steps(*plan, target(true));
    replay_ = std::move(plan);
  }
  bool replays() const { return replay_ != nullptr; }

  // The next frame's plan, for a tree T_D of `leaves` leaves and fronts of `front_nodes`
  // nodes in all, whose order updates in place have decayed by `disorder` (the largest
  // FrontQuery::disorder of the queries); `ahead_done`: the build ahead, if one runs, has
  // finished on its stream (a decided plan adopts it then; a replayed one where recorded).
  FramePlan plan(uint32_t leaves, uint64_t front_nodes, double disorder = 0.0, bool ahead_done = false) {
    FramePlan p = replay_ ? replayed() : in_flight_ ? in_flight(ahead_done) : decided(leaves, front_nodes);
    const bool updates = p.updates();
    // In place while the fronts' order has decayed by less than the compact share; the
    // update after produces them whole and ordered.
    p.in_place = updates && config_.fronts.update_in_place && disorder < config_.fronts.compact_share;
    // Balance orders a front by the offsets of the sort that produced it: not one with holes
    // and an appended tail.
    p.balance = strategy_.balance && updates && !p.in_place && disorder == 0.0;
    return p;
  }

  // What a plan runs, as a plan records it: the queries that do not run have no operation.
  PlanStep step(const FramePlan& p) const {
    PlanStep s;
    s.trees = p.rebuild ? TreeStep::build
              : p.ahead ? (p.ahead_update ? TreeStep::update_ahead : TreeStep::ahead)
              : p.adopt ? (p.ahead_update ? TreeStep::adopt_update : TreeStep::adopt)
              : p.stale ? TreeStep::stale
                        : TreeStep::refit;
    for (Query q : kQueries)
      if (running_[size_t(q)]) s.op(q) = p.op(q);
    s.decision = p.decision;
    s.inspect = p.inspect;
    s.probe = p.probe;
    return s;
  }

  // After the frame ran, what it measured.
  struct Outcome {
    double ms = 0.0;          // its cost without upload
    bool ran_once = true;     // no buffer grew, so its operations ran once
    uint64_t front_nodes = 0; // the fronts it started from, all queries, all kinds
    double q_root = 0.0;      // internal over external self-front nodes after it
    Candidates found = {};    // what its inspection found (capped at the candidates' buffer)
    bool recorded = false;    // it recorded its frame graph (a one-off cost)
    double generate_per_node_ms = -1.0;  // a build frame: its generate and ordering per front node made
    uint64_t pairs = 0;       // the pairs it reported
    uint64_t update_yield = 0;  // a probing frame: the front nodes an update would make at most
    double first_pass_ms = -1.0;  // a frame that ran again: its first pass, without upload
    double ahead_ms = -1.0;       // an adopting frame: what the build ahead took on its stream
  };
  // An adopting frame counts as the build (or, adopting fronts updated ahead, as the
  // update): its cost is the frame's plus the side's, which ran beside earlier frames (a
  // bound: it shared the device with them).
  void finish(const FramePlan& p, const Outcome& o) {
    const FrontOp self = p.op(Query::self);
    const bool adopted_update = p.adopt && p.ahead_update;
    const bool built = p.rebuild || (p.adopt && !p.ahead_update);
    const bool steady = p.steady() && !p.stale && !p.adopt, clean = o.ran_once && !o.recorded;
    // A build frame that ran again is priced by its first pass: the growth and the second
    // pass are one-offs, and counted whole they made the first maintenance's price a guess
    // up to twice too dear (docs/front-maintenance.md).
    const double ms = p.rebuild && !o.ran_once && o.first_pass_ms >= 0.0 ? o.first_pass_ms
                      : p.adopt                                          ? o.ms + std::max(o.ahead_ms, 0.0)
                                                                         : o.ms;
    const FrameKind kind = built                       ? FrameKind::built
                           : adopted_update            ? FrameKind::updated
                           : steady                    ? FrameKind::steady
                           : self == FrontOp::update   ? FrameKind::updated
                           : self == FrontOp::generate ? FrameKind::generated
                                                       : FrameKind::other;
    maintenance_.observe({.kind = kind, .ms = ms, .front_nodes = o.front_nodes, .once = clean});
    tree_.observe(o.front_nodes, o.pairs, p.probe ? o.update_yield : 0);
    if (built) tree_.built();
    const bool fronts_changed = p.changes_fronts() || adopted_update;
    if (!built && fronts_changed) tree_.maintained();
    if (p.rebuild && o.generate_per_node_ms >= 0.0) maintenance_.observe_build_generate(o.generate_per_node_ms);
    if (self == FrontOp::restructure)
      price_.observe_restructure(ms, p.restructuring.leaves, clean);
    else if (steady && clean)
      price_.observe_steady(ms, o.pairs);
    if (kind == FrameKind::updated && clean) price_.observe_update(ms);
    if (built || self == FrontOp::update || self == FrontOp::generate || adopted_update) {
      price_.maintained(frame_ - maintained_);
      maintained_ = frame_;
    }
    if (built || self == FrontOp::generate) generated_ = frame_;
    if (built || fronts_changed) {
      produced_ = frame_;
      maintenance_.produced();
    }
    if (strategy_.restructure && built) q_ref_ = o.q_root;
    if (p.inspect) pending_ = o.found;
    probed_ = p.probe;
    // A cycle begins at each maintenance: a build ahead, or an update or generate of T_D's
    // self fronts (in its frame, or an update ahead: not a new tree, so --maintain-ahead
    // auto prices it as an update; a restructure continues its update's cycle).
    const bool in_frame =
        (!built && (self == FrontOp::update || self == FrontOp::generate)) || (p.ahead && p.ahead_update);
    choice_.observe(o.ms, o.pairs,
                    p.rebuild                    ? std::optional{MaintenanceWay::none}
                    : p.ahead && !p.ahead_update ? std::optional{MaintenanceWay::ahead}
                    : in_frame ? std::optional{MaintenanceWay::in_frame}
                               : std::nullopt);
    if (p.ahead) {
      in_flight_ = true;
      in_flight_update_ = p.ahead_update;
    }
    if (p.adopt) in_flight_ = in_flight_update_ = false;
    ++frame_;
  }

  uint64_t frame() const { return frame_; }
  // A build or update ahead runs: launched, not adopted yet.
  bool ahead_in_flight() const { return in_flight_; }
  // Q of the root after the last rebuild (pipeline c's reference quality; 0 before one).
  double q_ref() const { return q_ref_; }

 private:
  // The frame's plan from the frame counter, the measured costs and the last inspection.
  FramePlan decided(uint32_t leaves, uint64_t front_nodes) {
    FramePlan p;
    p.decision = formula2(leaves, front_nodes);
    if (p.decision != Formula2::none) p.restructuring = pending_;
    pending_ = {};
    // A maintenance due on a degraded tree rebuilds it instead (pipeline/tree_maintenance.h).
    // An adaptive one that comes due unprobed waits a frame for its probe, which sizes its
    // buffers and measures the tree (FrontMaintenance::update_near).
    FrontOp due = maintenance_op(front_nodes);
    // --maintain-ahead: the maintenance is a rebuild built ahead, off the frames' critical
    // path, and needs no probe.
    const bool ahead_maintenance = maintains_ahead() && due != FrontOp::preserve && p.decision != Formula2::restructure;
    if (due != FrontOp::preserve && maintenance_.adaptive() && config_.fronts.update_probe && !probed_ &&
        p.decision != Formula2::restructure && !ahead_maintenance)
      due = FrontOp::preserve;
    p.rebuild = strategy_.rebuild_every_frame || p.decision == Formula2::rebuild ||
                rebuild_due(frame_, config_.tree.rebuild_every) || (due != FrontOp::preserve && tree_.rebuild_due()) ||
                ahead_maintenance;
    // --refit-every: between refits both trees keep their last boxes (not conservative).
    p.stale = !p.rebuild && !refit_due(frame_, config_.tree.refit_every);
    // The self fronts of T_D follow the maintenance rule, or restructure. The cross fronts
    // name T_D's leaves, which a rebuild or a restructure renumbers: they regenerate then.
    // T_R is only refitted after its build, so its self fronts follow the rule.
    const FrontOp cycle = p.rebuild ? FrontOp::generate : due;
    const bool restructure = !p.rebuild && p.decision == Formula2::restructure;
    p.op(Query::self) = restructure ? FrontOp::restructure : cycle;
    p.op(Query::inter) = restructure ? FrontOp::generate : cycle;
    p.op(Query::rigid_self) = cycle;
    // Inspected after a maintenance (the paper's circle 3: an update, or a generate chosen
    // instead) only: right after a rebuild Q is the reference, and a restructure keeps the
    // stale front for the next maintenance to refresh.
    p.inspect = strategy_.restructure && q_ref_ > 0.0 &&
                (p.op(Query::self) == FrontOp::update || (p.op(Query::self) == FrontOp::generate && !p.rebuild));
    // The probe rides on a preserve (a restructure frame's self fronts do not preserve).
    p.probe = config_.fronts.update_probe && !maintains_ahead() && !p.rebuild && step(p).runs(FrontOp::preserve) &&
              maintenance_.update_near(frame_, generated_, produced_, front_nodes);
    // Built ahead: the frame refits and preserves, and the rebuild runs beside it and the
    // frames after it (FramePlan::ahead), which preserve until it is adopted (in_flight).
    // The first frame has no tree to preserve on: it builds.
    if (p.rebuild && builds_ahead_ && frame_ > 0) {
      p.rebuild = false;
      p.ahead = true;
      p.ops = {FrontOp::preserve, FrontOp::preserve, FrontOp::preserve};
      p.inspect = p.probe = false;
      p.restructuring = {};
    }
    // --update-ahead: a due update of T_D's self fronts runs on the side from the current
    // fronts (FramePlan::ahead_update); the frame and the ones after it preserve until the
    // updated fronts are adopted. Pipeline c inspects nothing after it.
    if (updates_ahead() && frame_ > 0 && !p.rebuild && !p.ahead && p.op(Query::self) == FrontOp::update) {
      p.ahead = p.ahead_update = true;
      p.ops = {FrontOp::preserve, FrontOp::preserve, FrontOp::preserve};
      p.inspect = p.probe = false;
    }
    return p;
  }

  // A frame while a build ahead runs: every front preserved, nothing inspected or probed;
  // the build adopted once done. Formula 2 waits for the inspection after the adopted tree's
  // first maintenance.
  FramePlan in_flight(bool ahead_done) {
    FramePlan p;
    p.adopt = ahead_done;
    p.ahead_update = in_flight_update_;
    pending_ = {};
    return p;
  }

  ReplayTarget target(bool builds_ahead) const {
    return {strategy_.restructure, strategy_.rebuild_every_frame, config_.tree.refit_every, builds_ahead};
  }

  // The frame's recorded step (checked by replay and reset), with the candidates this
  // run's inspection on the frame before found.
  FramePlan replayed() {
    const RecordedPlan& r = *replay_;
    if (frame_ >= r.frames.size())
      fail(r.source + ": the plan records " + std::to_string(r.frames.size()) + " frames, and the run has more");
    const PlanStep& s = r.frames[frame_].step;
    FramePlan p;
    p.rebuild = s.trees == TreeStep::build;
    p.stale = s.trees == TreeStep::stale;
    p.ahead = s.trees == TreeStep::ahead || s.trees == TreeStep::update_ahead;
    p.adopt = s.trees == TreeStep::adopt || s.trees == TreeStep::adopt_update;
    p.ahead_update = s.trees == TreeStep::update_ahead || s.trees == TreeStep::adopt_update;
    for (Query q : kQueries) p.op(q) = s.op(q).value_or(FrontOp::preserve);
    p.decision = s.decision;
    p.inspect = s.inspect;
    if (p.op(Query::self) == FrontOp::restructure) {
      if (pending_.count == 0)
        fail(r.where(frame_) + ": restructure, but this run's inspection of the frame before found no degraded "
                               "subtree (the recording's did: the two inspections differ)");
      p.restructuring = pending_;
    }
    pending_ = {};
    // The recorded probes; in a plan that records none, a preserve before a recorded update
    // probes, as one before a decided update would.
    const bool probed = r.records_probes ? s.probe
                                         : !p.rebuild && s.runs(FrontOp::preserve) && frame_ + 1 < r.frames.size() &&
                                               r.frames[frame_ + 1].step.runs(FrontOp::update);
    p.probe = config_.fronts.update_probe && probed;
    return p;
  }

  // The paper prints the rebuild and restructure branches the other way round; restructuring
  // many subtrees costs more than a rebuild and restructuring few is what it is for, so here
  // a large share rebuilds (docs/design.md).
  Formula2 formula2(uint32_t leaves, uint64_t front_nodes) const {
    if (!strategy_.restructure || pending_.count == 0) return Formula2::none;
    const double share = double(pending_.leaves) / double(std::max<uint32_t>(leaves, 1));
    if (share < config_.restructure.threshold_refit) return Formula2::refit;
    if (share >= config_.restructure.threshold_build) return Formula2::rebuild;
    // A restructure this run measured not to pay only refits (pipeline/restructure_price.h).
    return price_.pays(pending_.leaves, pending_.front_nodes, front_nodes) ? Formula2::restructure : Formula2::refit;
  }

  // What the maintenance rule runs on a refitted tree this frame (preserve: none due).
  FrontOp maintenance_op(uint64_t front_nodes) const {
    if (!maintenance_.update_due(frame_, generated_, produced_, front_nodes)) return FrontOp::preserve;
    // periodic: every second maintenance generates. With a fixed cycle that is every second
    // cycle since the last generate; adaptively, the maintenance after an update.
    if (strategy_.periodic) {
      if (maintenance_.adaptive() ? produced_ > generated_ : ((frame_ - generated_) / config_.fronts.cycle) % 2 == 0)
        return FrontOp::generate;
      return FrontOp::update;
    }
    // Adaptive: a generate where one measured cheaper than an update (FrontMaintenance).
    return maintenance_.generate_due() ? FrontOp::generate : FrontOp::update;
  }

  FrontStrategy strategy_;
  PipelineConfig config_;
  FrontMaintenance maintenance_;
  TreeMaintenance tree_;
  RestructurePrice price_;
  MaintenanceChoice choice_;
  uint64_t frame_ = 0;
  uint64_t generated_ = 0;  // the last frame that generated T_D's self fronts
  uint64_t produced_ = 0;   // the last frame that produced any front
  uint64_t maintained_ = 0; // the last frame that built, updated or generated T_D's self fronts
  bool probed_ = false;     // the last frame probed
  bool builds_ahead_ = false;  // rebuilds after the first frame are built ahead (reset)
  bool in_flight_ = false;  // a build or update ahead runs: launched, not adopted yet
  bool in_flight_update_ = false;  // what runs is an update ahead
  Candidates pending_;      // found by the last inspection, decided on the next frame
  QuerySet running_ = {true, true, true};       // the queries that run in the scene
  std::shared_ptr<const RecordedPlan> replay_;  // the plan replayed, or none
  double q_ref_ = 0.0;      // Q of the root after the last rebuild (pipeline c)
};

}  // namespace cdb
