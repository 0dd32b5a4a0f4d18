#include "scenes/load/composed_scene.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

class ComposedScene final : public FrameSource {
 public:
  ComposedScene(std::vector<ScenePart> parts, uint32_t frames) : parts_(std::move(parts)), frames_(frames) {
    if (parts_.empty()) fail("a composed scene needs at least one part");
    for (const ScenePart& p : parts_) {
      const Topology& t = p.source->topology();
      if (p.source->num_frames() < frames_)
        fail("part '" + p.name + "' has " + std::to_string(p.source->num_frames()) + " frames, the scene " +
             std::to_string(frames_));
      const uint32_t base = topology_.num_vertices, first_face = uint32_t(topology_.faces.size());
      first_vertex_.push_back(base);
      for (const Tri& f : t.faces) topology_.faces.push_back({base + f.v0, base + f.v1, base + f.v2});
      topology_.num_vertices += t.num_vertices;
      topology_.box_faces += t.box_faces;
      topology_.objects.push_back({p.name, first_face, uint32_t(t.faces.size()), p.rigid});
    }
  }
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return frames_; }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= frames_) fail("frame " + std::to_string(k) + " out of range (" + std::to_string(frames_) + " frames)");
    out.resize(topology_.num_vertices);
    std::vector<vec3d> part;
    for (size_t p = 0; p < parts_.size(); ++p) {
      parts_[p].source->positions(k, part);
      std::copy(part.begin(), part.end(), out.begin() + first_vertex_[p]);
    }
  }
  std::string describe() const override {
    std::string d = std::to_string(topology_.faces.size()) + " triangles in " + std::to_string(parts_.size()) +
                    " parts, " + std::to_string(frames_) + " frames:";
    for (const ScenePart& p : parts_) d += " " + p.name + " (" + p.source->describe() + ");";
    d.pop_back();
    return d;
  }

 private:
  std::vector<ScenePart> parts_;
  uint32_t frames_;
  std::vector<uint32_t> first_vertex_;
  Topology topology_;
};

class Crowd final : public FrameSource {
 public:
  explicit Crowd(const CrowdOptions& o) : o_(o), clip_(open_animated_clip(o.animation)) {
    if (o.count == 0) fail("crowd: count must be at least 1");
    if (o.up_axis < 0 || o.up_axis > 2) fail("crowd: the up axis must be x, y or z");
    if (!(o.spacing > 0)) fail("crowd: spacing must be positive");
    const Topology& one = clip_->topology();
    const uint64_t faces = uint64_t(one.faces.size()) * o.count, vertices = uint64_t(one.num_vertices) * o.count;
    if (faces > UINT32_MAX || vertices > UINT32_MAX)
      fail("crowd: " + std::to_string(o.count) + " instances of " + std::to_string(one.faces.size()) +
           " triangles exceed 32-bit indices");
    clip_seconds_ = clip_->clip_seconds();
    columns_ = o.columns ? o.columns : uint32_t(std::ceil(std::sqrt(double(o.count))));
    frames_ = o.frames ? o.frames : uint32_t(std::floor(clip_seconds_ * o.animation.fps + 1e-9)) + 1;
    const double step = o.phase_step >= 0 ? o.phase_step : 0.6180339887498949 * clip_seconds_;
    std::vector<vec3f> rest;
    clip_->positions_at(o.animation.start, rest);
    float lo[3] = {rest[0].x, rest[0].y, rest[0].z}, hi[3] = {lo[0], lo[1], lo[2]};
    for (const vec3f& p : rest) {
      const float c[3] = {p.x, p.y, p.z};
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
    }
    const int across = (o.up_axis + 1) % 3, along = (o.up_axis + 2) % 3;
    for (uint32_t i = 0; i < o.count; ++i) {
      double offset[3] = {0, 0, 0};
      offset[across] = o.spacing * (hi[across] - lo[across]) * (i % columns_);
      offset[along] = o.spacing * (hi[along] - lo[along]) * (i / columns_);
      offsets_.push_back({offset[0], offset[1], offset[2]});
      phases_.push_back(clip_seconds_ > 0 ? std::fmod(i * step, clip_seconds_) : 0.0);
      const uint32_t base = i * one.num_vertices, first_face = uint32_t(topology_.faces.size());
      for (const Tri& f : one.faces) topology_.faces.push_back({base + f.v0, base + f.v1, base + f.v2});
      if (o.instance_objects)
        topology_.objects.push_back({o.name + "#" + std::to_string(i), first_face, uint32_t(one.faces.size()), false});
    }
    topology_.num_vertices = uint32_t(vertices);
    if (!o.instance_objects) topology_.objects.push_back({o.name, 0, uint32_t(faces), false});
  }

  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return frames_; }

  // Instance i at frame k plays the clip at (start + phase_i + k / fps) mod clip length.
  double instance_time(uint32_t i, uint32_t k) const {
    const double t = o_.animation.start + phases_[i] + k / o_.animation.fps;
    return clip_seconds_ > 0 ? std::fmod(t, clip_seconds_) : o_.animation.start;
  }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= frames_) fail(o_.name + ": frame " + std::to_string(k) + " out of range (" + std::to_string(frames_) + " frames)");
    const uint32_t n = clip_->topology().num_vertices;
    out.resize(topology_.num_vertices);
    std::vector<vec3f> one;
    for (uint32_t i = 0; i < o_.count; ++i) {
      clip_->positions_at(instance_time(i, k), one);
      const auto& d = offsets_[i];
      for (uint32_t v = 0; v < n; ++v)
        out[size_t(i) * n + v] = {one[v].x + d[0], one[v].y + d[1], one[v].z + d[2]};
    }
    check_frame(out, topology_, o_.name, k);
  }

  std::string describe() const override {
    return "crowd of " + std::to_string(o_.count) + " x " + std::to_string(clip_->topology().faces.size()) + " = " +
           std::to_string(topology_.faces.size()) + " triangles (" + o_.animation.file.string() + ", " +
           std::to_string(columns_) + " columns, spacing " + std::to_string(o_.spacing) + "), " +
           std::to_string(frames_) + " frames at " + std::to_string(o_.animation.fps) + " fps";
  }

 private:
  CrowdOptions o_;
  std::unique_ptr<AnimatedClip> clip_;
  double clip_seconds_ = 0;
  uint32_t columns_ = 1, frames_ = 1;
  std::vector<std::array<double, 3>> offsets_;
  std::vector<double> phases_;
  Topology topology_;
};

}  // namespace

std::unique_ptr<FrameSource> compose_parts(std::vector<ScenePart> parts, uint32_t frames) {
  return std::make_unique<ComposedScene>(std::move(parts), frames);
}

std::unique_ptr<FrameSource> open_crowd(const CrowdOptions& options) { return std::make_unique<Crowd>(options); }

}  // namespace cdb
