#pragma once
// When a front pipeline rebuilds its hierarchy on its own (--rebuild-degraded G): a
// maintenance due (pipeline/front_maintenance.h) rebuilds the tree and generates every
// front, instead of updating the fronts on the refitted tree, once an update would make
// fronts of more than G times the nodes per pair the fronts had right after the last build.
//
// A refitted tree degrades as the geometry drifts from the one it was built on: its boxes
// grow and overlap, so a front that finds the same pairs needs more nodes. An update or a
// generate fits the fronts to the tree, not the tree to the scene: on a degraded tree it
// makes large fronts, and every steady frame after it pays for them. A rebuild frame costs
// about what an update frame costs and brings the fronts back to a build's size (figures:
// docs/front-maintenance.md "Rebuilding a degraded tree"). The size of an update is known
// before it runs: the preserves before an update probe what it yields at most
// (FrontQuery::reserve_for_update). Nodes per pair divides out contact that grows with the
// scene. A maintenance with no probe before it (--update-probe off, or rent that reached the
// price in one frame) updates as before.
#include <algorithm>
#include <cstdint>

namespace cdb {

class TreeMaintenance {
 public:
  // growth: G above; 0 never rebuilds.
  explicit TreeMaintenance(double growth = 0.0) : growth_(growth) {}

  void reset() { *this = TreeMaintenance(growth_); }

  // Whether a maintenance due now should rebuild the tree instead.
  bool rebuild_due() const { return growth_ > 0.0 && fresh_ > 0.0 && probed_ > growth_ * fresh_; }

  // Front nodes per pair right after the last build, and what the last probe since the
  // fronts were produced says an update would make (0: not measured).
  double fresh_per_pair() const { return fresh_; }
  double probed_per_pair() const { return probed_; }

  // The tree was built and every front generated: the next frame measures their size.
  void built() {
    fresh_pending_ = true;
    probed_ = 0.0;
  }

  // The fronts were produced again on the same tree: the last probe no longer describes them.
  void fronts_produced() { probed_ = 0.0; }

  // A frame that started from fronts of `front_nodes` nodes and reported `pairs`; `yield`:
  // the nodes its probe counted an update would make, or 0 if it did not probe.
  void observe(uint64_t front_nodes, uint64_t pairs, uint64_t yield) {
    const double n = double(std::max<uint64_t>(pairs, 1));
    if (fresh_pending_) fresh_ = double(front_nodes) / n;
    fresh_pending_ = false;
    if (yield > 0) probed_ = double(yield) / n;
  }

 private:
  double growth_;
  bool fresh_pending_ = false;
  double fresh_ = 0.0;
  double probed_ = 0.0;
};

}  // namespace cdb
