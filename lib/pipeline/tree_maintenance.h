#pragma once
// When a front pipeline rebuilds its hierarchy on its own (--tree-rebuild auto): rent or buy
// on the tree's degradation, beside the fronts' (pipeline/front_maintenance.h).
//
// A refitted tree degrades as the geometry drifts from the one it was built on: its boxes
// grow and overlap, so a front that finds the same pairs needs more nodes. An update or a
// generate fits the fronts to the tree, not the tree to the scene, so the steady frame right
// after one stays dear: the fronts' rent starts over while the tree's share of the cost
// stays. That share is what this rent measures. Each steady frame pays the cheapest steady
// frame since the fronts were last produced (fresh fronts, so what the tree costs) over what
// a steady frame cost per pair on the fresh tree, times the frame's pairs: contact that
// grows with the scene raises the expected cost and is not rent. The tree is rebuilt (and
// every front generated) once the rent paid reaches what the last build frame cost over a
// steady frame after it. Scenes whose tree keeps its quality, where an update brings the
// steady frame back, pay no rent and never rebuild.
#include <algorithm>
#include <cstdint>
#include <limits>

namespace cdb {

class TreeMaintenance {
 public:
  explicit TreeMaintenance(bool enabled = false) : enabled_(enabled) {}

  void reset() { *this = TreeMaintenance(enabled_); }

  bool rebuild_due() const { return enabled_ && priced_ && rent_ms_ >= price_ms_; }

  double rent_ms() const { return rent_ms_; }
  double price_ms() const { return price_ms_; }

  // A frame that built the tree, at cost `ms`: the rent starts over, priced by the next
  // steady frame.
  void built(double ms) {
    build_ms_ = ms;
    rent_ms_ = 0.0;
    priced_ = false;
    fresh_stretch_ = true;
    fresh_per_pair_ = std::numeric_limits<double>::infinity();
  }

  // The fronts were produced again (update, generate, restructure) on the same tree: the
  // steady frames after it no longer measure the fresh tree.
  void fronts_produced() { fresh_stretch_ = false; }

  // A steady frame of `pairs` pairs at `ms`; `fronts_fresh_ms`: the cheapest steady frame
  // since the fronts were last produced (this one included).
  void steady(double ms, double fronts_fresh_ms, uint64_t pairs) {
    const double n = double(std::max<uint64_t>(pairs, 1));
    if (!priced_) {
      price_ms_ = std::max(0.0, build_ms_ - ms);
      priced_ = true;
    }
    if (fresh_stretch_) fresh_per_pair_ = std::min(fresh_per_pair_, ms / n);
    rent_ms_ += std::max(0.0, fronts_fresh_ms - fresh_per_pair_ * n);
  }

 private:
  bool enabled_;
  bool priced_ = false;        // a steady frame after the build measured the price
  bool fresh_stretch_ = true;  // no front produced since the build
  double build_ms_ = 0.0;
  double price_ms_ = 0.0;
  double rent_ms_ = 0.0;
  double fresh_per_pair_ = std::numeric_limits<double>::infinity();
};

}  // namespace cdb
