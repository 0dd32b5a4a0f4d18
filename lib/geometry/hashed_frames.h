#pragma once
// A frame source that hashes each frame the first time it passes through (core/content_hash.h),
// so a run learns its input's content hash from the frames it loads anyway: no second pass
// over a long sequence. Hashing happens in positions(), which the run loop calls before the
// pipeline's timed frame, never inside it; later passes (--repeat, several pipelines) find
// the frame's hash already taken.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/core/content_hash.h"
#include "cdbench/geometry/frame_source.h"

namespace cdb {

class HashedFrames final : public FrameSource {
 public:
  explicit HashedFrames(const FrameSource& source) : source_(source), hashes_(source.num_frames()) {}
  const Topology& topology() const override { return source_.topology(); }
  uint32_t num_frames() const override { return source_.num_frames(); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    source_.positions(k, out);
    if (k < hashes_.size() && !hashes_[k]) {
      ContentHash h;
      h.add_bytes(out.data(), out.size() * sizeof(vec3d));
      hashes_[k] = h.value();
    }
  }
  std::string describe() const override { return source_.describe(); }

  // The hash of the topology (faces, vertex count, objects, declared queries) and of frames
  // [first, last) in order; none while some frame of the range has not passed through.
  std::optional<uint64_t> input_hash(uint32_t first, uint32_t last) const {
    const Topology& t = source_.topology();
    ContentHash h;
    h.add(t.num_vertices);
    h.add_bytes(t.faces.data(), t.faces.size() * sizeof(Tri));
    for (const SceneObject& o : t.objects) {
      h.add_bytes(o.name.data(), o.name.size());
      h.add((uint64_t(o.first_face) << 32) | o.num_faces);
      h.add(o.rigid);
    }
    h.add(t.queries.declared);
    for (uint32_t s : t.queries.self) h.add(s);
    for (const auto& [a, b] : t.queries.inter) h.add((uint64_t(a) << 32) | b);
    h.add((uint64_t(first) << 32) | last);
    for (uint32_t k = first; k < last; ++k) {
      if (k >= hashes_.size() || !hashes_[k]) return std::nullopt;
      h.add(*hashes_[k]);
    }
    return h.value();
  }

 private:
  const FrameSource& source_;
  mutable std::vector<std::optional<uint64_t>> hashes_;
};

}  // namespace cdb
