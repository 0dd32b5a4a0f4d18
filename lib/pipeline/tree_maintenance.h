#pragma once
// When a front pipeline rebuilds its hierarchy on its own (--rebuild-degraded on): a
// maintenance due (pipeline/front_maintenance.h) rebuilds the tree and generates every
// front, instead of updating the fronts on the refitted tree, once the rent its fronts paid
// on the tree since the build reaches a rebuild's cost over an update's.
//
// A refitted tree degrades as the geometry drifts from the one it was built on: its boxes
// grow and overlap, so a front that finds the same pairs needs more nodes. An update or a
// generate fits the fronts to the tree, not the tree to the scene: on a degraded tree it
// makes large fronts, and every steady frame after it pays for them. A rebuild brings the
// fronts back to a build's size (figures: docs/front-maintenance.md "Rebuilding a degraded
// tree"). Rent or buy, in front nodes per pair, which divides out contact that grows with
// the scene: with F the fronts' nodes per pair right after the last build, a steady frame
// on fronts of R nodes per pair pays 1 - F/R of its cost as rent on the tree (a preserve
// leaves the fronts' size as the last maintenance made it, so R is measured, not guessed).
// The rebuild's cost over a steady frame is the last rebuild frame's after the first (the
// first pays first-launch costs), or before one ran, kRebuildPerSteady steady frames; the
// update's is the maintenance price, once an update was measured (before, it comes from the
// first frame, which also pays first-launch costs: the planner updates). Fronts right after a
// build pay no rent, so the first maintenance after one updates: the tree shows its
// degradation in what the update makes.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "exec/tuning.h"

namespace cdb {

class TreeMaintenance {
 public:
  explicit TreeMaintenance(bool enabled = false) : enabled_(enabled) {}

  void reset() { *this = TreeMaintenance(enabled_); }

  // Whether a maintenance due now should rebuild the tree: `steady_ms`, the cheapest steady
  // frame on the current fronts; `update_ms`, what an update costs over a steady frame.
  bool rebuild_due(double steady_ms, double update_ms) const {
    if (!enabled_ || rent_ms_ <= 0.0 || !(steady_ms > 0.0) || !std::isfinite(steady_ms)) return false;
    const double rebuild_ms = rebuild_ms_ > 0.0 ? rebuild_ms_ : kRebuildPerSteady * steady_ms;
    return rent_ms_ >= rebuild_ms - steady_ms - update_ms;
  }

  // The rent paid on the tree since its build, in ms; the fronts' nodes per pair right after it.
  double rent_ms() const { return rent_ms_; }
  double fresh_per_pair() const { return fresh_; }

  // A frame that started from fronts of `front_nodes` nodes and reported `pairs`;
  // `steady_ms`: its cost if it was a steady frame that ran clean, else negative.
  void observe(uint64_t front_nodes, uint64_t pairs, double steady_ms) {
    const double per_pair = double(front_nodes) / double(std::max<uint64_t>(pairs, 1));
    if (fresh_pending_) fresh_ = per_pair;
    fresh_pending_ = false;
    if (steady_ms > 0.0 && fresh_ > 0.0 && per_pair > fresh_) rent_ms_ += steady_ms * (1.0 - fresh_ / per_pair);
  }

  // The tree was built and every front generated, at `ms` (`clean`: ran once, recorded no
  // graph; the first build is not clean either): the next frame measures the fronts' size.
  void built(double ms, bool clean) {
    if (clean) rebuild_ms_ = ms;
    fresh_pending_ = true;
    rent_ms_ = 0.0;
  }

 private:
  bool enabled_;
  bool fresh_pending_ = false;
  double fresh_ = 0.0;
  double rent_ms_ = 0.0;
  double rebuild_ms_ = 0.0;  // the last rebuild frame after the first that ran clean
};

}  // namespace cdb
