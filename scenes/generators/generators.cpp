#include "scenes/generators/generators.h"

#include <new>

#include <cmath>

#include "scenes/generators/cloth_scenes.h"
#include "cdbench/core/error.h"
#include "scenes/generators/crumple.h"
#include "scenes/generators/n_body.h"
#include "scenes/generators/paper_scenes.h"
#include "scenes/generators/params.h"
#include "scenes/generators/rng.h"

namespace cdb {
namespace {

using scene::Params;
using scene::Rng;

class GeneratedSource : public FrameSource {
 public:
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return frames_; }
  std::string describe() const override { return description_; }

 protected:
  Topology topology_;
  uint32_t frames_ = 1;
  std::string description_;
};

void add_grid_faces(Topology& t, uint32_t base, uint32_t nu, uint32_t nv) {
  for (uint32_t j = 0; j + 1 < nv; ++j)
    for (uint32_t i = 0; i + 1 < nu; ++i) {
      const uint32_t a = base + j * nu + i, b = a + 1, c = a + nu, d = c + 1;
      t.faces.push_back({a, b, d});
      t.faces.push_back({a, d, c});
    }
}

// Random triangle soup: the property tests' workhorse. Centroids uniform in a cube,
// in Gaussian clusters, or all at one point; optional duplicated faces; frames jitter every
// vertex a little.
class SoupSource final : public GeneratedSource {
 public:
  explicit SoupSource(Params& p) {
    // Three vertices a triangle, indexed by 32 bits.
    n_ = p.count32("triangles", 1000, 0, UINT32_MAX / 3);
    const std::string dist = p.text("distribution", "uniform");
    scale_ = p.number("scale", 1.0);
    const double size = p.number("size", 0.5 / std::cbrt(double(std::max<uint64_t>(n_, 1))));
    const double duplicates = p.number("duplicates", 0.0);
    jitter_ = p.number("jitter", 0.1) * size;
    seed_ = p.count_in("seed", 1, 0, scene::kLargestExactCount);
    frames_ = p.count32("frames", 1, 1, UINT32_MAX);
    p.finish();
    if (dist != "uniform" && dist != "clustered" && dist != "identical")
      fail("generator 'soup', parameter 'distribution': unknown value '" + dist +
           "' (uniform, clustered, identical)");
    if (frames_ == 0) fail("generator 'soup', parameter 'frames': must be at least 1");
    Rng rng{seed_};
    base_.reserve(3 * n_);
    std::vector<vec3<double>> centers;
    for (int c = 0; c < 8; ++c) centers.push_back({rng.uniform(), rng.uniform(), rng.uniform()});
    for (uint64_t t = 0; t < n_; ++t) {
      vec3<double> c{0.5, 0.5, 0.5};
      if (dist == "uniform") c = {rng.uniform(), rng.uniform(), rng.uniform()};
      if (dist == "clustered") {
        const auto& m = centers[rng.next() % centers.size()];
        c = {m.x + 0.1 * rng.normal(), m.y + 0.1 * rng.normal(), m.z + 0.1 * rng.normal()};
      }
      const vec3<double> d1{rng.symmetric() * size, rng.symmetric() * size, rng.symmetric() * size};
      const vec3<double> d2{rng.symmetric() * size, rng.symmetric() * size, rng.symmetric() * size};
      // Vertices c+d1, c+d2, c-d1-d2: the centroid is c.
      base_.push_back({c.x + d1.x, c.y + d1.y, c.z + d1.z});
      base_.push_back({c.x + d2.x, c.y + d2.y, c.z + d2.z});
      base_.push_back({c.x - d1.x - d2.x, c.y - d1.y - d2.y, c.z - d1.z - d2.z});
      const bool dup = t > 0 && rng.uniform() < duplicates;
      const uint32_t v = uint32_t(3 * t);
      if (dup) {
        topology_.faces.push_back(topology_.faces[rng.next() % topology_.faces.size()]);
      } else {
        topology_.faces.push_back({v, v + 1, v + 2});
      }
    }
    topology_.num_vertices = uint32_t(3 * n_);
    description_ = "soup: " + std::to_string(n_) + " triangles, " + dist;
    dist_ = dist;
  }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    out.resize(base_.size());
    Rng rng{seed_ * 7919 + k};
    const double j = k == 0 || dist_ == "identical" ? 0.0 : jitter_;
    for (size_t v = 0; v < base_.size(); ++v) {
      const auto& b = base_[v];
      out[v] = {(b.x + j * rng.symmetric()) * scale_, (b.y + j * rng.symmetric()) * scale_,
                (b.z + j * rng.symmetric()) * scale_};
    }
  }

 private:
  uint64_t n_ = 0, seed_ = 1;
  double scale_ = 1.0, jitter_ = 0.0;
  std::string dist_;
  std::vector<vec3<double>> base_;
};

// A square cloth with a wave travelling across it while its far edge rolls up over the
// sheet (a spiral, so the rolled layers come close and touch: self-contact).
class ClothWaveSource final : public GeneratedSource {
 public:
  explicit ClothWaveSource(Params& p) {
    res_ = p.count32("res", 64, 2, 20000);
    frames_ = p.count32("frames", 20, 1, UINT32_MAX);
    p.finish();
    add_grid_faces(topology_, 0, res_, res_);
    topology_.num_vertices = res_ * res_;
    description_ = "cloth-wave: " + std::to_string(res_) + "x" + std::to_string(res_) + " cloth";
  }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    out.resize(size_t(res_) * res_);
    const double t = frames_ > 1 ? double(k) / (frames_ - 1) : 0.0;
    const double roll_start = 0.85 - 0.45 * t;  // the roll eats into the sheet over time
    const double radius = 0.06;
    for (uint32_t j = 0; j < res_; ++j)
      for (uint32_t i = 0; i < res_; ++i) {
        const double s = double(i) / (res_ - 1), z = double(j) / (res_ - 1);
        double x = s, y = 0.03 * std::sin(12.0 * s - 8.0 * t + 3.0 * z);
        if (s > roll_start) {
          const double theta = (s - roll_start) / radius;
          const double r = radius * std::max(0.2, 1.0 - 0.04 * theta);
          x = roll_start + r * std::sin(theta);
          y += r * (1.0 - std::cos(theta));
        }
        out[size_t(j) * res_ + i] = {x, y, z};
      }
  }

 private:
  uint32_t res_ = 64;
};

}  // namespace

const std::vector<std::string>& generator_names() {
  static const std::vector<std::string> names = {"soup",   "cloth-wave", "funnel", "cloth-ball", "flag",
                                                    "sphere", "n-body",     "flamenco", "dragon",
                                                    "crumple"};
  return names;
}

namespace {

std::unique_ptr<FrameSource> make_named(const std::string& name, Params& p, const scene::SceneInputs* inputs) {
  if (name == "soup") return std::make_unique<SoupSource>(p);
  if (name == "cloth-wave") return std::make_unique<ClothWaveSource>(p);
  if (name == "funnel") return scene::make_funnel(p);
  if (name == "cloth-ball") return scene::make_cloth_ball(p);
  if (name == "flag") return scene::make_flag(p);
  if (name == "sphere") return scene::make_sphere_hit(p);
  if (name == "n-body") return scene::make_n_body(p);
  if (name == "crumple") return scene::make_crumple(p);
  if (name == "flamenco" || name == "dragon") {
    if (!inputs) fail("generator '" + name + "' reads packaged files: open it as a scene (a descriptor), not alone");
    return name == "flamenco" ? scene::make_flamenco(p, *inputs) : scene::make_dragon(p, *inputs);
  }
  std::string list;
  for (const auto& n : generator_names()) list += (list.empty() ? "" : ", ") + n;
  fail("unknown generator '" + name + "' (known: " + list + ")");
}

}  // namespace

std::unique_ptr<FrameSource> make_generator(const std::string& name, const nlohmann::json& params,
                                            std::vector<GeneratorParameter>* described,
                                            const scene::SceneInputs* inputs) {
  Params p(name, params);
  try {
    std::unique_ptr<FrameSource> source = make_named(name, p, inputs);
    if (described) *described = p.described();
    return source;
  } catch (const std::bad_alloc&) {
    // The sizes are the parameters: name them, with what they were.
    std::string sizes;
    for (const auto& d : p.described())
      if (d.kind == "integer" && d.value != d.fallback) sizes += (sizes.empty() ? "" : ", ") + d.key + "=" + d.value;
    fail("generator '" + name + "': out of host memory building the scene" +
         (sizes.empty() ? std::string() : " with " + sizes) + "; lower its size parameters");
  }
}

}  // namespace cdb
