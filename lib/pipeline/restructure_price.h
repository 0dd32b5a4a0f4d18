#pragma once
// Whether pipeline c's restructure (paper §4.2, operation 5) pays for itself, measured
// (--restructure-price on, the default). Formula 2 decides from the share of leaves in
// degraded subtrees alone, with the paper's thresholds; whether restructuring them saves
// more on the frames after it than the restructure frame costs depends on the scene and the
// card, and the decision here comes from what this run measured.
//
// A restructure's cost is its frame's time over the cheapest steady frame of the last stretch
// that had one (what the frame would have cost preserving: a restructure follows the update
// whose inspection found its candidates, so its own stretch has none), per restructured leaf. Its gain is
// the front nodes it removed (the fronts the next frame starts from against those the
// restructure frame started from), per restructured leaf, times what a steady frame pays per
// front node (the last steady frame's time over its fronts), times the frames its smaller
// fronts are kept: the length of the last stretch between two maintenances (updates,
// generates or builds). A restructure
// runs where the gain so predicted for the candidates found is at least the cost so
// predicted, and one that pays keeps measuring each, so a restructure that grew dear or
// stopped gaining gives way. Before the first of a run is measured, a bound decides: a
// restructure removes at most the front nodes in its candidates (the inspection counts
// them), and its frame costs at least what the update before it cost over preserving:
// both are one front pass over every front node that produces new ones (measured: a
// restructure 3.5x a steady frame on flamenco, 4.8x on the garment with its avatar, whose
// update before was 2.9x), and at least one steady frame. It runs where removing them for a
// stretch would pay for that, so a scene whose candidates hold few front nodes does not
// spend a restructure on learning that it does not pay. Not all of them go: the candidates'
// fronts are regenerated, and a generated front holds as many nodes a pair as the fronts
// had on the frame after their last generate or build. So of the candidates' nodes the
// bound counts the share the fronts have grown by since, per pair (1 - fresh / now): on the
// H200 at 7354d62 the first restructures of flamenco and the garment with its avatar came
// where the fronts held 5.9 and 8.5 nodes a pair against 3.3 and 5.2 fresh, and neither paid
// (c 1.12x and 1.15x b's mean, results/2026-12-03-h200/bar).
//
// Figures (NVIDIA H200, one pass, phases timed): on flamenco a restructure of 3,217 leaves
// cost 0.46 ms against a 0.13 ms steady frame and removed 6% of the front nodes; the
// preserves after it were no cheaper than b's after an update (docs/design.md).
#include <algorithm>
#include <cstdint>
#include <limits>

namespace cdb {

class RestructurePrice {
 public:
  explicit RestructurePrice(bool enabled = true) : enabled_(enabled) {}

  // Forget every measurement (a new run over the frames).
  void reset() { *this = RestructurePrice(enabled_); }

  bool measured() const { return cost_per_leaf_ms_ >= 0.0 && gain_per_leaf_ >= 0.0; }

  // Whether restructuring candidates of `leaves` leaves holding `front_nodes` front nodes,
  // of fronts of `all_front_nodes` in all, is predicted to pay (always when disabled; by the
  // bound before one was measured, and before a steady frame was, too).
  bool pays(uint32_t leaves, uint64_t front_nodes, uint64_t all_front_nodes) const {
    if (!enabled_) return true;
    if (!measured()) return bound_pays(front_nodes, all_front_nodes);
    return predicted_gain_ms(leaves) >= predicted_cost_ms(leaves);
  }
  // The bound: the candidates' front nodes in excess of fresh fronts (removable_share)
  // removed for the stretch, at a steady frame's cost per node, against the last update's
  // cost over preserving, or one steady frame where that was less or not measured.
  bool bound_pays(uint64_t front_nodes, uint64_t all_front_nodes) const {
    const double steady = preserving_ms();
    if (!(steady < kNone)) return true;
    return double(front_nodes) * removable_share(all_front_nodes) * steady_per_node_ms_ * double(horizon_) >=
           std::max(steady, update_over_steady_ms_);
  }
  // The share of fronts of `all_front_nodes` nodes, for the last frame's pairs, that fronts
  // as fresh as after a generate would not hold: 1 before a fresh front was measured.
  double removable_share(uint64_t all_front_nodes) const {
    if (fresh_per_pair_ <= 0.0 || last_pairs_ == 0 || all_front_nodes == 0) return 1.0;
    const double now = double(all_front_nodes) / double(last_pairs_);
    return std::clamp(1.0 - fresh_per_pair_ / now, 0.0, 1.0);
  }
  double predicted_cost_ms(uint32_t leaves) const { return std::max(cost_per_leaf_ms_, 0.0) * double(leaves); }
  double predicted_gain_ms(uint32_t leaves) const {
    return std::max(gain_per_leaf_, 0.0) * double(leaves) * steady_per_node_ms_ * double(horizon_);
  }

  // A steady frame (refit + preserve, run once) of `ms` from fronts of `front_nodes` nodes.
  void observe_steady(double ms, uint64_t front_nodes) {
    stretch_min_ = std::min(stretch_min_, ms);
    steady_per_node_ms_ = ms / double(std::max<uint64_t>(front_nodes, 1));
    if (after_restructure_) gain_from(front_nodes);
  }

  // A frame that restructured candidates of `leaves` leaves in `ms`, from fronts of
  // `front_nodes` nodes; `once`: it ran its operations once (a frame that grew a buffer
  // paid a one-off cost, not the restructure's).
  void observe_restructure(double ms, uint32_t leaves, uint64_t front_nodes, bool once) {
    const double preserving = preserving_ms();
    if (once && preserving < kNone && leaves > 0) cost_per_leaf_ms_ = std::max(0.0, ms - preserving) / double(leaves);
    restructured_leaves_ = leaves;
    fronts_before_ = front_nodes;
    after_restructure_ = true;
  }

  // A frame that updated the fronts in `ms`, its operations run once: what it cost over the
  // cheapest steady frame of its stretch, or of the last one (before the update ends it).
  void observe_update(double ms) {
    const double preserving = preserving_ms();
    if (preserving < kNone) update_over_steady_ms_ = std::max(0.0, ms - preserving);
  }

  // Any other frame after a restructure: its fronts measure the restructure's gain too.
  void observe_other(uint64_t front_nodes) {
    if (after_restructure_) gain_from(front_nodes);
  }

  // Every frame, after the calls above: the fronts it started from and the pairs it
  // reported; `fresh`: it generated the fronts (a build, an adoption or a generate), so the
  // next frame starts from fresh ones.
  void observe_fronts(uint64_t front_nodes, uint64_t pairs, bool fresh) {
    if (fresh_next_ && pairs > 0) fresh_per_pair_ = double(front_nodes) / double(pairs);
    fresh_next_ = fresh;
    last_pairs_ = pairs;
  }

  // A maintenance (update, generate or build) `frames` frames after the last one: the
  // stretch a maintenance's fronts are kept. A new stretch of steady frames starts.
  void maintained(uint64_t frames) {
    if (frames > 0) horizon_ = frames;
    if (stretch_min_ < kNone) last_stretch_min_ = stretch_min_;
    stretch_min_ = kNone;
  }

 private:
  // What a frame costs preserving: the cheapest steady frame of this stretch or the last
  // one that had one (kNone before any).
  double preserving_ms() const { return std::min(stretch_min_, last_stretch_min_); }

  void gain_from(uint64_t front_nodes) {
    after_restructure_ = false;
    if (restructured_leaves_ == 0) return;
    gain_per_leaf_ = (double(fronts_before_) - double(front_nodes)) / double(restructured_leaves_);
  }

  static constexpr double kNone = std::numeric_limits<double>::infinity();

  bool enabled_;
  double cost_per_leaf_ms_ = -1.0;  // the last measured restructure's cost per leaf (-1: none)
  double gain_per_leaf_ = -1.0;     // front nodes it removed per leaf (-1: none)
  double steady_per_node_ms_ = 0.0;  // the last steady frame's time per front node
  double update_over_steady_ms_ = 0.0;  // the last update's cost over a steady frame
  double stretch_min_ = kNone;       // the cheapest steady frame since the last maintenance
  double last_stretch_min_ = kNone;  // the same for the last stretch that had steady frames
  uint64_t horizon_ = 1;             // frames between the last two productions of the fronts
  double fresh_per_pair_ = 0.0;      // front nodes a pair on the frame after the last generate
  bool fresh_next_ = false;          // the last frame generated the fronts
  uint64_t last_pairs_ = 0;          // the pairs the last frame reported
  uint32_t restructured_leaves_ = 0;
  uint64_t fronts_before_ = 0;
  bool after_restructure_ = false;
};

}  // namespace cdb
