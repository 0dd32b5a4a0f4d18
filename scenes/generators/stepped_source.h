#pragma once
// A scene whose frames come from one state advanced a frame at a time (a simulation, a
// flow): frame k is the state after k advances from frame 0's. Frames are made on demand
// and in order; asking for an earlier frame starts over from frame 0's state, so memory
// stays at a copy or two of the state however many frames the scene has.
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/geometry/frame_source.h"

namespace cdb::scene {

template <class State>
class SteppedSource : public FrameSource {
 public:
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return frames_; }
  std::string describe() const override { return description_; }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= frames_) fail("frame " + std::to_string(k) + " out of range (" + std::to_string(frames_) + " frames)");
    std::lock_guard<std::mutex> lock(mutex_);
    if (!first_) first_.emplace(first());
    if (!current_ || current_frame_ > k) {
      current_ = *first_;
      current_frame_ = 0;
    }
    for (; current_frame_ < k; ++current_frame_) advance(*current_, current_frame_);
    write(*current_, out);
  }

 protected:
  // Frame 0's state (after any warm-up), made once, on the first frame asked for.
  virtual State first() const = 0;
  // From frame `from`'s state to the next frame's.
  virtual void advance(State& state, uint32_t from) const = 0;
  virtual void write(const State& state, std::vector<vec3d>& out) const = 0;

  Topology topology_;
  uint32_t frames_ = 1;
  std::string description_;

 private:
  mutable std::mutex mutex_;
  mutable std::optional<State> first_, current_;
  mutable uint32_t current_frame_ = 0;
};

}  // namespace cdb::scene
