#pragma once
// A frame source that keeps every frame it has produced, so that several pipelines run one
// after another on the same scene (cdbench run --pipeline a,b,c) pay for simulating or
// loading each frame once. Memory: frames x vertices x 24 bytes (double positions); the caller decides
// whether that fits.
#include <memory>
#include <optional>
#include <vector>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

class CachedFrames final : public FrameSource {
 public:
  explicit CachedFrames(const FrameSource& source) : source_(source), frames_(source.num_frames()) {}
  const Topology& topology() const override { return source_.topology(); }
  uint32_t num_frames() const override { return source_.num_frames(); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k < frames_.size() && frames_[k]) {
      out = *frames_[k];
      return;
    }
    source_.positions(k, out);
    if (k < frames_.size()) frames_[k] = out;
  }
  std::string describe() const override { return source_.describe(); }

 private:
  const FrameSource& source_;
  mutable std::vector<std::optional<std::vector<vec3d>>> frames_;
};

}  // namespace cdb
