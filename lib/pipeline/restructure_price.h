#pragma once
// Whether pipeline c's restructure (paper §4.2, operation 5) pays for itself, measured
// (--restructure-price on, the default). Formula 2 decides from the share of leaves in
// degraded subtrees alone, with the paper's thresholds; whether restructuring them saves
// more on the frames after it than the restructure frame costs depends on the scene and the
// card, and the decision here comes from what this run measured, in time.
//
// The frames between two maintenances (updates, generates or builds) form a stretch; a
// restructure follows the update whose inspection found its candidates, so it begins a
// stretch too, one that began restructured. A stretch's steady frames (refit + preserve)
// say what its fronts cost: their mean per pair reported, and their rent, what they cost
// over the stretch's cheapest one, summed (the staleness FrontMaintenance prices an update
// against). A restructure's cost is its frame's time over the cheapest steady frame of the
// last stretch that had one (what the frame would have cost preserving), per restructured
// leaf.
//
// Front nodes are not the measure of its gain. A restructure regenerates the candidates'
// fronts on rebuilt subtrees, and on the H200 at 98d591e flamenco's fronts after one held
// 2.55M nodes where b's after its update held 3.40M, yet preserved in 0.13-0.17 ms a frame
// against b's 0.09-0.12 (results/2026-12-03-h200/bar): the node count fell, the work did
// not. So:
// - Once a restructured stretch and a plain one (begun by an update or a build without a
//   restructure) were measured, a restructure runs where the plain one's mean per pair over
//   the restructured one's, at the last steady frame's pairs, for a stretch, covers the
//   measured cost; one that paid keeps being measured, so one that stopped paying gives way.
// - Before, a bound decides: a restructure saves at most the last stretch's rent, in the
//   share of the fronts its candidates hold (the inspection counts their front nodes), and
//   costs at least what the update before it cost over preserving (both are one front pass
//   over every front node that produces new ones; measured: a restructure 3.5x a steady frame
//   on flamenco, 4.8x on the garment with its avatar, whose update before was 2.9x), and at
//   least one steady frame. On the H200 at 98d591e a bound on front nodes let flamenco
//   restructure twice, and c ran 1.16x b's mean.
#include <algorithm>
#include <cstdint>
#include <limits>

namespace cdb {

class RestructurePrice {
 public:
  explicit RestructurePrice(bool enabled = true) : enabled_(enabled) {}

  // Forget every measurement (a new run over the frames).
  void reset() { *this = RestructurePrice(enabled_); }

  // Measured: a restructured stretch and a plain one, and a restructure's cost.
  bool measured() const { return cost_per_leaf_ms_ >= 0.0 && restructured_per_pair_ >= 0.0 && plain_per_pair_ >= 0.0; }

  // Whether restructuring candidates of `leaves` leaves holding `front_nodes` front nodes,
  // of fronts of `all_front_nodes` in all, is predicted to pay (always when disabled).
  bool pays(uint32_t leaves, uint64_t front_nodes, uint64_t all_front_nodes) const {
    if (!enabled_) return true;
    if (!measured()) return bound_pays(front_nodes, all_front_nodes);
    return predicted_gain_ms() >= predicted_cost_ms(leaves);
  }
  // The bound: the last stretch's rent in the candidates' share of the fronts, against the
  // last update's cost over preserving, or one steady frame where that was less. Nothing
  // to judge by (no stretch with steady frames yet): no restructure.
  bool bound_pays(uint64_t front_nodes, uint64_t all_front_nodes) const {
    const double steady = preserving_ms();
    if (!(steady < kNone) || last_rent_ms_ < 0.0) return false;
    const double share = all_front_nodes > 0 ? std::min(1.0, double(front_nodes) / double(all_front_nodes)) : 1.0;
    return last_rent_ms_ * share >= std::max(steady, update_over_steady_ms_);
  }
  double predicted_cost_ms(uint32_t leaves) const { return std::max(cost_per_leaf_ms_, 0.0) * double(leaves); }
  // What a stretch of restructured fronts saved against plain ones, at the last steady
  // frame's pairs.
  double predicted_gain_ms() const {
    return (plain_per_pair_ - restructured_per_pair_) * double(last_pairs_) * double(horizon_);
  }
  // The last stretch's rent (-1 before a stretch with steady frames ended).
  double last_rent_ms() const { return last_rent_ms_; }

  // A steady frame (refit + preserve, run once) of `ms` that reported `pairs`.
  void observe_steady(double ms, uint64_t pairs) {
    stretch_min_ = std::min(stretch_min_, ms);
    stretch_ms_ += ms;
    stretch_per_pair_ += ms / double(std::max<uint64_t>(pairs, 1));
    ++stretch_steady_;
    last_pairs_ = pairs;
  }

  // A frame that restructured candidates of `leaves` leaves in `ms`; `once`: it ran its
  // operations once (a frame that grew a buffer paid a one-off cost, not the restructure's).
  // Its stretch began restructured.
  void observe_restructure(double ms, uint32_t leaves, bool once) {
    const double preserving = preserving_ms();
    if (once && preserving < kNone && leaves > 0) cost_per_leaf_ms_ = std::max(0.0, ms - preserving) / double(leaves);
    restructured_ = true;
  }

  // A frame that updated the fronts in `ms`, its operations run once: what it cost over the
  // cheapest steady frame of its stretch, or of the last one (before the update ends it).
  void observe_update(double ms) {
    const double preserving = preserving_ms();
    if (preserving < kNone) update_over_steady_ms_ = std::max(0.0, ms - preserving);
  }

  // A maintenance (update, generate or build) `frames` frames after the last one: the
  // stretch a maintenance's fronts are kept. The stretch ends and a new one starts.
  void maintained(uint64_t frames) {
    if (frames > 0) horizon_ = frames;
    if (stretch_steady_ > 0) {
      last_stretch_min_ = stretch_min_;
      last_rent_ms_ = stretch_ms_ - double(stretch_steady_) * stretch_min_;
      (restructured_ ? restructured_per_pair_ : plain_per_pair_) = stretch_per_pair_ / double(stretch_steady_);
    }
    stretch_min_ = kNone;
    stretch_ms_ = stretch_per_pair_ = 0.0;
    stretch_steady_ = 0;
    restructured_ = false;
  }

 private:
  // What a frame costs preserving: the cheapest steady frame of this stretch or the last
  // one that had one (kNone before any).
  double preserving_ms() const { return std::min(stretch_min_, last_stretch_min_); }

  static constexpr double kNone = std::numeric_limits<double>::infinity();

  bool enabled_;
  double cost_per_leaf_ms_ = -1.0;      // the last measured restructure's cost per leaf (-1: none)
  double update_over_steady_ms_ = 0.0;  // the last update's cost over a steady frame
  double plain_per_pair_ = -1.0;        // mean steady ms per pair, the last plain stretch (-1: none)
  double restructured_per_pair_ = -1.0; // the same, the last restructured stretch
  double last_rent_ms_ = -1.0;          // the last stretch's rent (-1: none)
  uint64_t last_pairs_ = 0;             // the last steady frame's pairs
  uint64_t horizon_ = 1;                // frames between the last two maintenances
  // The current stretch.
  double stretch_min_ = kNone;       // its cheapest steady frame
  double last_stretch_min_ = kNone;  // the same for the last stretch that had steady frames
  double stretch_ms_ = 0.0, stretch_per_pair_ = 0.0;  // its steady frames' ms, and ms per pair, summed
  uint64_t stretch_steady_ = 0;      // its steady frames
  bool restructured_ = false;        // a restructure began it
};

}  // namespace cdb
