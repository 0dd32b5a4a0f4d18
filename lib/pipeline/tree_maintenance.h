#pragma once
// When a front pipeline rebuilds its hierarchy on its own (--rebuild-degraded on): a
// maintenance due (pipeline/front_maintenance.h) rebuilds the tree and generates every
// front, instead of updating the fronts on the refitted tree, when the tree has degraded.
//
// A refitted tree degrades as the geometry drifts from the one it was built on: its boxes
// grow and overlap, so a front that finds the same pairs needs more nodes. An update or a
// generate fits the fronts to the tree, not the tree to the scene: on a degraded tree it
// makes large fronts, and every steady frame after it pays for them. A rebuild brings the
// fronts back to a build's size (figures: docs/front-maintenance.md "Rebuilding a degraded
// tree"). Fronts are measured in nodes per pair, which divides out contact that grows with
// the scene; F is the fronts' nodes per pair right after the last build. A front counts at
// least one wave of the device's resident threads: a preserve spreads a smaller front over
// a wave (front/warp_traversal.h), so it costs a wave's latency, however many nodes it has
// (the funnel's steady frame stays 0.032-0.035 ms from 204K to 339K nodes, H200).
//
// The first maintenance after a build has nothing measured to price a rebuild against (the
// first frame pays first-launch costs, and no update has run on this tree): it rebuilds when
// the probe before it (FrontQuery::update_yield) counts that an update would grow the fronts,
// which are still the build's, more than kFirstUpdateGrowth times. Counted in nodes, not per
// pair: where contact thins out (the funnel) a per-pair count grows without the fronts.
//
// Later maintenances rent or buy: a steady frame on fronts of R nodes per pair pays 1 - F/R
// of its cost as rent on the tree (a preserve leaves the fronts' size as the last
// maintenance made it, so R is measured, not guessed), and a maintenance rebuilds once the
// rent since the build reaches a rebuild's cost over an update's. The rebuild's cost over a
// steady frame is the last rebuild frame's after the first (the first pays first-launch
// costs), or before one ran, kRebuildPerSteady steady frames; the update's is the
// maintenance price, once an update was measured (before, it comes from the first frame,
// which also pays first-launch costs: the planner updates).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "exec/tuning.h"

namespace cdb {

class TreeMaintenance {
 public:
  explicit TreeMaintenance(bool enabled = false) : enabled_(enabled) {}

  // A new run; `wave`: the device's resident threads, the fewest nodes a front counts as.
  void reset(uint64_t wave = 1) {
    *this = TreeMaintenance(enabled_);
    wave_ = std::max<uint64_t>(wave, 1);
  }

  // Whether a maintenance due now should rebuild the tree: `steady_ms`, the cheapest steady
  // frame on the current fronts; `update_ms`, what an update costs over a steady frame, or
  // negative where no update was measured yet.
  bool rebuild_due(double steady_ms, double update_ms) const {
    if (!enabled_) return false;
    if (!maintained_) return probed_ > kFirstUpdateGrowth;
    if (update_ms < 0.0 || rent_ms_ <= 0.0 || !(steady_ms > 0.0) || !std::isfinite(steady_ms)) return false;
    const double rebuild_ms = rebuild_ms_ > 0.0 ? rebuild_ms_ : kRebuildPerSteady * steady_ms;
    return rent_ms_ >= rebuild_ms - steady_ms - update_ms;
  }

  // The rent paid on the tree since its build, in ms; the fronts' nodes per pair right after
  // it (counting at least a wave).
  double rent_ms() const { return rent_ms_; }
  double fresh_per_pair() const { return fresh_; }
  // What the last probe since the fronts were produced counted an update would make, over
  // the fronts it probed (both counting at least a wave; 0: no probe).
  double probed_growth() const { return probed_; }

  // A frame that started from fronts of `front_nodes` nodes and reported `pairs`;
  // `steady_ms`: its cost if it was a steady frame that ran clean, else negative;
  // `update_yield`: the front nodes its probe counted an update would make (0: no probe).
  void observe(uint64_t front_nodes, uint64_t pairs, double steady_ms, uint64_t update_yield = 0) {
    const double n = double(std::max<uint64_t>(pairs, 1)), per_pair = double(std::max(front_nodes, wave_)) / n;
    if (fresh_pending_) fresh_ = per_pair;
    fresh_pending_ = false;
    if (update_yield > 0) probed_ = double(std::max(update_yield, wave_)) / double(std::max(front_nodes, wave_));
    if (steady_ms > 0.0 && fresh_ > 0.0 && per_pair > fresh_) rent_ms_ += steady_ms * (1.0 - fresh_ / per_pair);
  }

  // The tree was built and every front generated, at `ms` (`clean`: ran once, recorded no
  // graph; the first build is not clean either): the next frame measures the fronts' size.
  void built(double ms, bool clean) {
    if (clean) rebuild_ms_ = ms;
    fresh_pending_ = true;
    maintained_ = false;
    rent_ms_ = probed_ = 0.0;
  }

  // A maintenance produced fronts on the refitted tree: the last probe no longer describes them.
  void maintained() {
    maintained_ = true;
    probed_ = 0.0;
  }

 private:
  bool enabled_;
  uint64_t wave_ = 1;
  bool fresh_pending_ = false;
  bool maintained_ = false;  // fronts were produced on the tree since its build
  double fresh_ = 0.0;
  double probed_ = 0.0;
  double rent_ms_ = 0.0;
  double rebuild_ms_ = 0.0;  // the last rebuild frame after the first that ran clean
};

}  // namespace cdb
