#pragma once
// When a front pipeline rebuilds its hierarchy on its own (--rebuild-degraded on): a
// maintenance due (pipeline/front_maintenance.h) rebuilds the tree and generates every
// front, instead of updating the fronts on the refitted tree, when the tree has degraded
// fast.
//
// A refitted tree degrades as the geometry drifts from the one it was built on: its boxes
// grow and overlap, so a front that finds the same pairs needs more nodes. An update or a
// generate fits the fronts to the tree, not the tree to the scene: on a degraded tree it
// makes large fronts, and every steady frame after it pays for them. A rebuild brings the
// fronts back to a build's size (figures: docs/front-maintenance.md "Rebuilding a degraded
// tree"). The probe before a maintenance (FrontQuery::update_yield) counts what an update
// would make; a rebuild would make F nodes per pair, F being the fronts' nodes per pair right
// after the last build, times the probed frame's pairs (which divides out contact that grows
// or thins with the scene). Each counts at least one wave of the device's resident threads:
// a preserve spreads a smaller front over a wave (front/warp_traversal.h), so it costs a
// wave's latency however many nodes it has.
//
// The maintenance rebuilds when the update's count is more than a growth G times the
// rebuild's (--rebuild-growth, default kRebuildGrowth), and the tree got there fast: that growth, less one, over the frames since the
// build, is more than kRebuildRate. A tree that degrades slowly is one whose neighbourhoods
// hold under the motion, as a tree of a cloth built on its flat rest shape does while the
// cloth drapes; a Morton tree rebuilt on the folded cloth groups folds that slide apart and
// degrades many times faster (cloth-ball). Where the motion breaks neighbourhoods (bodies
// that scatter, incoherent frames) every tree degrades fast, and rebuilds pay.
#include <algorithm>
#include <cstdint>

#include "cdbench/exec/tuning.h"

namespace cdb {

class TreeMaintenance {
 public:
  explicit TreeMaintenance(bool enabled = false) : enabled_(enabled) {}

  // A new run; `wave`: the device's resident threads, the fewest nodes a front counts as;
  // `rebuild_growth`: G.
  void reset(uint64_t wave = 1, double rebuild_growth = kRebuildGrowth) {
    *this = TreeMaintenance(enabled_);
    wave_ = std::max<uint64_t>(wave, 1);
    rebuild_growth_ = rebuild_growth;
  }

  // Whether a maintenance due now should rebuild the tree.
  bool rebuild_due() const { return enabled_ && growth_ > rebuild_growth_ && probed_rate() > kRebuildRate; }

  // The fronts' nodes per pair right after the last build, and what the last probe since
  // the fronts were produced counted an update would make over what a rebuild would
  // (0: no probe).
  double fresh_per_pair() const { return fresh_; }
  double rebuild_growth() const { return rebuild_growth_; }
  double probed_growth() const { return growth_; }
  // That growth, less one, per frame since the build (0: no probe).
  double probed_rate() const { return growth_ > 0.0 ? (growth_ - 1.0) / double(std::max<uint32_t>(age_, 1)) : 0.0; }

  // A frame that started from fronts of `front_nodes` nodes and reported `pairs`;
  // `update_yield`: the front nodes its probe counted an update would make (0: no probe).
  void observe(uint64_t front_nodes, uint64_t pairs, uint64_t update_yield = 0) {
    ++age_;
    if (fresh_pending_) fresh_ = double(front_nodes) / double(std::max<uint64_t>(pairs, 1));
    fresh_pending_ = false;
    if (update_yield == 0 || fresh_ <= 0.0) return;
    const double rebuilt = std::max(fresh_ * double(pairs), double(wave_));
    growth_ = double(std::max(update_yield, wave_)) / rebuilt;
  }

  // The tree was built and every front generated: the next frame measures the fronts' size.
  void built() {
    fresh_pending_ = true;
    growth_ = 0.0;
    age_ = 0;
  }

  // A maintenance produced fronts on the refitted tree: the last probe no longer describes them.
  void maintained() { growth_ = 0.0; }

 private:
  bool enabled_;
  uint64_t wave_ = 1;
  double rebuild_growth_ = kRebuildGrowth;
  bool fresh_pending_ = false;
  double fresh_ = 0.0;
  double growth_ = 0.0;
  uint32_t age_ = 0;  // frames observed since the last build, the probing frame included
};

}  // namespace cdb
