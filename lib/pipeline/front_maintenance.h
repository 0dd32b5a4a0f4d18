#pragma once
// When a front pipeline updates its fronts (paper Fig. 4, operation 3) instead of preserving
// them (2). Preserving stale fronts is exact (a front partitions its leaf's range however
// stale: front/front.h), but its cost grows as the geometry drifts from the fronts; an update
// costs more than a preserve once and starts the growth over.
//
// Fixed cycle (--front-cycle K, the paper's scheme): every K-th frame since the fronts were
// generated updates.
//
// Adaptive (--front-cycle auto): rent or buy, on measured frame times. Each steady frame
// (refit + preserve) since the fronts were last produced pays rent: its cost over the
// cheapest steady frame of the same stretch, i.e. what the fronts' staleness costs. The
// fronts update once the rent paid reaches what an update costs over a steady frame, as last
// measured. For rent that grows linearly with time (a per frame) this updates every
// sqrt(2U/a) frames, the best fixed cycle's length; whatever the growth, the total stays
// within twice that of the best schedule in hindsight (the ski-rental bound). Scenes whose
// fronts barely degrade update rarely, scenes whose fronts degrade fast often, and timing
// noise alone only lets the rent creep up, so an update still comes now and then.
// Until an update has been measured, the frame that built the tree and generated the fronts
// stands for one: its cost over a steady frame overestimates an update's (a build and a
// traversal from every leaf's start, against sprouting and pruning from the front), so the
// first update comes late rather than early; every later one is judged on measured updates.
#include <algorithm>
#include <cstdint>
#include <limits>

namespace cdb {

class FrontMaintenance {
 public:
  static constexpr uint32_t kAuto = 0;

  // cycle: frames per fixed cycle, or kAuto.
  explicit FrontMaintenance(uint32_t cycle = kAuto) : cycle_(cycle) {}

  bool adaptive() const { return cycle_ == kAuto; }

  // Forget every measurement (a new run over the frames).
  void reset() { *this = FrontMaintenance(cycle_); }

  // Whether the frame `frame` should update fronts generated at `generated` and last
  // produced (generated, updated or restructured) at `produced`.
  bool update_due(uint64_t frame, uint64_t generated, uint64_t produced) const {
    if (!adaptive()) return frame > generated && (frame - generated) % cycle_ == 0;
    return frame > produced && steady_ > 0 && rent_ms() >= update_cost_ms();
  }

  // What an update is taken to cost over a steady frame, in ms: the last measured updates,
  // or before any, the build frame's cost over the cheapest steady frame since.
  double update_cost_ms() const {
    if (update_ms_ >= 0.0) return update_ms_;
    return steady_ > 0 ? std::max(0.0, build_ms_ - steady_min_) : 0.0;
  }

  // The rent paid since the fronts were last produced, in ms.
  double rent_ms() const { return steady_ > 0 ? steady_sum_ - double(steady_) * steady_min_ : 0.0; }
  // What the last measured updates cost over a steady frame, in ms (negative: none yet).
  double update_ms() const { return update_ms_; }

  // A frame's measured cost: `steady` for refit + preserve frames, `updated` for frames
  // whose fronts were updated (and nothing heavier ran with it), `built` for frames that
  // built the tree and generated the fronts.
  void observe(bool steady, bool updated, bool built, double ms) {
    if (built) build_ms_ = ms;
    if (steady) {
      steady_sum_ += ms;
      steady_min_ = std::min(steady_min_, ms);
      ++steady_;
      return;
    }
    if (updated && steady_ > 0) {
      // Over the cheapest steady frame before it: the cost of a steady frame on fresh fronts.
      const double extra = std::max(0.0, ms - steady_min_);
      update_ms_ = update_ms_ < 0.0 ? extra : 0.5 * (update_ms_ + extra);
    }
  }

  // The fronts were produced this frame: the rent starts over.
  void produced() {
    steady_sum_ = 0.0;
    steady_min_ = std::numeric_limits<double>::infinity();
    steady_ = 0;
  }

 private:
  uint32_t cycle_;
  double update_ms_ = -1.0;
  double build_ms_ = 0.0;
  double steady_sum_ = 0.0;
  double steady_min_ = std::numeric_limits<double>::infinity();
  uint64_t steady_ = 0;
};

}  // namespace cdb
