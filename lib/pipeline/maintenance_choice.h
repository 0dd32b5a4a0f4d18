#pragma once
// --maintain-ahead auto: whether a maintenance the front cycle asks for runs in its frame (an
// update or a generate) or as a rebuild built ahead (a new tree and fronts on the side
// stream, adopted frames later: pipeline/front_pipeline.h), by what each cost the last time.
//
// Neither price alone decides. A build ahead keeps its maintenance out of the frame, but
// the frames beside it share the GPU with the side stream, and a rebuilt tree may degrade
// faster than an updated front of the first one: on the H200 at a8d0401, every maintenance
// built ahead made crumple 1.16-1.21x faster and the dragon, garment and funnel-large 1.07-
// 1.15x, and cloth-ball 0.61-0.71x slower, whose rebuilds of the folded cloth are worse
// trees than the flat cloth's, so its maintenances came four times as often
// (results/2026-12-03-h200/maintain-ahead). So each maintenance starts a cycle that lasts
// until the next one, and a cycle's cost is what its frames cost per pair they reported: the
// maintenance, the frames beside a build ahead and the rent its fronts paid, normalized by
// the pairs because a scene's contact, and the time a frame takes with it, drifts between
// cycles while every pipeline reports the same pairs on a frame. The first maintenance of a
// run runs in its frame, the next one is built ahead (unless a rebuild on a degraded tree
// measured that already); from then on each runs the way whose last cycle cost less, which
// measures that way again, so a choice that grew dear gives way.
#include <cstddef>
#include <cstdint>
#include <optional>

namespace cdb {

// How a maintenance cycle began.
enum class MaintenanceWay {
  none,      // the first frame's build (no maintenance: not priced)
  in_frame,  // an update or generate of the self fronts in its frame
  ahead,     // a rebuild built ahead
};

class MaintenanceChoice {
 public:
  // Forget every measurement (a new run over the frames).
  void reset() { *this = MaintenanceChoice(); }

  // Whether the next maintenance should be built ahead. Asked when one is due, which ends
  // the current cycle: that one counts as finished with the frames it has.
  bool ahead_due() const {
    const double in_frame = cost(MaintenanceWay::in_frame), ahead = cost(MaintenanceWay::ahead);
    if (in_frame < 0.0) return false;
    if (ahead < 0.0) return true;
    return ahead < in_frame;
  }

  // Each frame of the run, in order: its time and pairs; `began`: the way of the cycle it
  // began (none: it continues the current one). A new cycle ends the last.
  void observe(double ms, uint64_t pairs, std::optional<MaintenanceWay> began = std::nullopt) {
    if (began) {
      if (current_ != MaintenanceWay::none && frames_ > 0) cost_[size_t(current_)] = current_cost();
      current_ = *began;
      ms_ = 0.0;
      pairs_ = frames_ = 0;
    }
    ms_ += ms;
    pairs_ += pairs;
    ++frames_;
  }

  // The cost of the last cycle begun `way` (the current one, up to its last frame), in ms
  // per pair (per frame where it reported none); -1 before one began.
  double cost(MaintenanceWay way) const {
    if (way == current_ && way != MaintenanceWay::none && frames_ > 0) return current_cost();
    return cost_[size_t(way)];
  }

 private:
  double current_cost() const { return ms_ / double(pairs_ > 0 ? pairs_ : frames_); }

  double cost_[3] = {-1.0, -1.0, -1.0};
  MaintenanceWay current_ = MaintenanceWay::none;
  double ms_ = 0.0;
  uint64_t pairs_ = 0, frames_ = 0;
};

}  // namespace cdb
