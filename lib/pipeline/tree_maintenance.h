#pragma once
// When a front pipeline rebuilds its hierarchy on its own (--rebuild-degraded on): a
// maintenance due (pipeline/front_maintenance.h) rebuilds the tree and generates every
// front, instead of updating the fronts on the refitted tree, when the steady frames the
// smaller fronts would save pay for the rebuild's cost over the update's.
//
// A refitted tree degrades as the geometry drifts from the one it was built on: its boxes
// grow and overlap, so a front that finds the same pairs needs more nodes. An update or a
// generate fits the fronts to the tree, not the tree to the scene: on a degraded tree it
// makes large fronts, and every steady frame after it pays for them. A rebuild brings the
// fronts back to a build's size, at a price (figures: docs/front-maintenance.md
// "Rebuilding a degraded tree"). Rent or buy, in front nodes per pair (which divides out
// contact that grows with the scene): with F the fronts' nodes per pair after the last build,
// a steady frame on fronts of R nodes per pair pays 1 - F/R of its cost as rent on the tree.
// At a maintenance, the rent paid since the build plus what the coming stretch would pay on
// the update's fronts (the preserves before an update probe what it makes:
// FrontQuery::reserve_for_update; the stretch taken as long as the one that ends now) is set
// against a rebuild's cost over an update's, both over a steady frame. The rebuild's is the
// last rebuild frame's after the first (the first pays first-launch costs), or before one
// ran, kRebuildPerSteady steady frames; the update's is the maintenance price. A maintenance
// with no probe before it (--update-probe off, or rent that reached the price in one frame)
// updates as before.
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
  // frame on the current fronts; `update_ms`, what an update costs over a steady frame;
  // `stretch`, the frames since the fronts were last produced.
  bool rebuild_due(double steady_ms, double update_ms, uint64_t stretch) const {
    if (!enabled_ || fresh_ <= 0.0 || probed_ <= 0.0 || !(steady_ms > 0.0) || !std::isfinite(steady_ms)) return false;
    const double rebuild_ms = (rebuild_ms_ > 0.0 ? rebuild_ms_ : kRebuildPerSteady * steady_ms) - steady_ms;
    return rent_ms_ + double(stretch) * steady_ms * share(probed_) > rebuild_ms - update_ms;
  }

  // The rent paid on the tree since its build, in ms.
  double rent_ms() const { return rent_ms_; }

  // Front nodes per pair right after the last build, and what the last probe since the
  // fronts were produced counts an update would make (0: not measured).
  double fresh_per_pair() const { return fresh_; }
  double probed_per_pair() const { return probed_; }

  // A frame that started from fronts of `front_nodes` nodes and reported `pairs`; `yield`:
  // the nodes its probe counted an update would make, or 0 if it did not probe; `steady_ms`:
  // its cost if it was a steady frame that ran clean, else negative.
  void observe(uint64_t front_nodes, uint64_t pairs, uint64_t yield, double steady_ms) {
    const double n = double(std::max<uint64_t>(pairs, 1));
    if (fresh_pending_) fresh_ = double(front_nodes) / n;
    fresh_pending_ = false;
    if (yield > 0) probed_ = double(yield) / n;
    if (steady_ms > 0.0) rent_ms_ += steady_ms * share(double(front_nodes) / n);
  }

  // The tree was built and every front generated, at `ms` (`clean`: ran once, recorded no
  // graph; the first build is not clean either): the next frame measures the fronts' size.
  void built(double ms, bool clean) {
    if (clean) rebuild_ms_ = ms;
    fresh_pending_ = true;
    probed_ = rent_ms_ = 0.0;
  }

  // The fronts were produced again on the same tree: the last probe no longer describes them.
  void fronts_produced() { probed_ = 0.0; }

 private:
  // The share of a steady frame on fronts of `per_pair` nodes per pair that is rent.
  double share(double per_pair) const { return fresh_ > 0.0 ? std::max(0.0, 1.0 - fresh_ / per_pair) : 0.0; }

  bool enabled_;
  bool fresh_pending_ = false;
  double fresh_ = 0.0;
  double probed_ = 0.0;
  double rent_ms_ = 0.0;
  double rebuild_ms_ = 0.0;  // the last rebuild frame after the first that ran clean
};

}  // namespace cdb
