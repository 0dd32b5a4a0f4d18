#include "generators.h"

#include <cmath>
#include <set>

#include "core/error.h"

namespace cdb {
namespace {

// splitmix64: a fixed, portable generator, so scenes are identical on every platform.
struct Rng {
  uint64_t s;
  uint64_t next() {
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
  double symmetric() { return 2.0 * uniform() - 1.0; }
  double normal() {
    const double u = std::max(uniform(), 1e-300), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(6.283185307179586 * v);
  }
};

// Reads generator parameters, remembering which were used so leftovers can be rejected.
class Params {
 public:
  Params(std::string generator, const nlohmann::json& j) : generator_(std::move(generator)), j_(j) {
    if (!j_.is_null() && !j_.is_object()) fail(where("") + "parameters must be a JSON object");
  }
  double number(const char* key, double fallback) {
    used_.insert(key);
    if (j_.is_null() || !j_.contains(key)) return fallback;
    if (!j_[key].is_number()) fail(where(key) + "must be a number");
    return j_[key].get<double>();
  }
  uint64_t count(const char* key, uint64_t fallback) {
    const double v = number(key, double(fallback));
    if (v < 0 || v != std::floor(v)) fail(where(key) + "must be a non-negative integer");
    return uint64_t(v);
  }
  std::string text(const char* key, const std::string& fallback) {
    used_.insert(key);
    if (j_.is_null() || !j_.contains(key)) return fallback;
    if (!j_[key].is_string()) fail(where(key) + "must be a string");
    return j_[key].get<std::string>();
  }
  void finish() const {
    if (j_.is_null()) return;
    for (auto it = j_.begin(); it != j_.end(); ++it)
      if (!used_.count(it.key())) fail(where(it.key()) + "unknown parameter");
  }

 private:
  std::string where(const std::string& key) const {
    return "generator '" + generator_ + "'" + (key.empty() ? "" : ", parameter '" + key + "'") + ": ";
  }
  std::string generator_;
  const nlohmann::json& j_;
  std::set<std::string> used_;
};

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
    n_ = p.count("triangles", 1000);
    const std::string dist = p.text("distribution", "uniform");
    scale_ = p.number("scale", 1.0);
    const double size = p.number("size", 0.5 / std::cbrt(double(std::max<uint64_t>(n_, 1))));
    const double duplicates = p.number("duplicates", 0.0);
    jitter_ = p.number("jitter", 0.1) * size;
    seed_ = p.count("seed", 1);
    frames_ = uint32_t(p.count("frames", 1));
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

  void frame(uint32_t k, std::vector<vec3f>& out) const override {
    out.resize(base_.size());
    Rng rng{seed_ * 7919 + k};
    const double j = k == 0 || dist_ == "identical" ? 0.0 : jitter_;
    for (size_t v = 0; v < base_.size(); ++v) {
      const auto& b = base_[v];
      out[v] = {float((b.x + j * rng.symmetric()) * scale_), float((b.y + j * rng.symmetric()) * scale_),
                float((b.z + j * rng.symmetric()) * scale_)};
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
    res_ = uint32_t(p.count("res", 64));
    frames_ = uint32_t(p.count("frames", 20));
    p.finish();
    if (res_ < 2) fail("generator 'cloth-wave', parameter 'res': must be at least 2");
    if (frames_ == 0) fail("generator 'cloth-wave', parameter 'frames': must be at least 1");
    add_grid_faces(topology_, 0, res_, res_);
    topology_.num_vertices = res_ * res_;
    description_ = "cloth-wave: " + std::to_string(res_) + "x" + std::to_string(res_) + " cloth";
  }

  void frame(uint32_t k, std::vector<vec3f>& out) const override {
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
        out[size_t(j) * res_ + i] = {float(x), float(y), float(z)};
      }
  }

 private:
  uint32_t res_ = 64;
};

// A cloth pushed down through a funnel: the cloth descends and is squeezed radially to the
// funnel's inner radius at its height; the squeezed cloth ruffles up the funnel wall in
// folds that touch each other. The funnel is a static cone mesh. Kinematic, not simulated.
class FunnelSource final : public GeneratedSource {
 public:
  explicit FunnelSource(Params& p) {
    res_ = uint32_t(p.count("res", 48));
    segments_ = uint32_t(p.count("funnel_segments", 48));
    frames_ = uint32_t(p.count("frames", 20));
    p.finish();
    if (res_ < 2) fail("generator 'funnel', parameter 'res': must be at least 2");
    if (segments_ < 3) fail("generator 'funnel', parameter 'funnel_segments': must be at least 3");
    if (frames_ == 0) fail("generator 'funnel', parameter 'frames': must be at least 1");
    add_grid_faces(topology_, 0, res_, res_);
    const uint32_t rings = 8;
    funnel_base_ = res_ * res_;
    // Cone wall: segments+1 columns (seam duplicated) by rings rows.
    add_grid_faces(topology_, funnel_base_, segments_ + 1, rings);
    topology_.num_vertices = funnel_base_ + (segments_ + 1) * rings;
    rings_ = rings;
    description_ = "funnel: " + std::to_string(res_) + "x" + std::to_string(res_) +
                   " cloth through a " + std::to_string(segments_) + "-segment funnel";
  }

  static double funnel_radius(double y) {  // cone from r=1.1 at y=0 to r=0.25 at y=-1.2
    const double u = std::min(1.0, std::max(0.0, -y / 1.2));
    return 1.1 + (0.25 - 1.1) * u;
  }

  void frame(uint32_t k, std::vector<vec3f>& out) const override {
    out.resize(topology_.num_vertices);
    const double t = frames_ > 1 ? double(k) / (frames_ - 1) : 0.0;
    const double drop = 0.3 - 1.2 * t;  // cloth centre height
    for (uint32_t j = 0; j < res_; ++j)
      for (uint32_t i = 0; i < res_; ++i) {
        const double u = 2.0 * i / (res_ - 1) - 1.0, v = 2.0 * j / (res_ - 1) - 1.0;
        const double rho = std::sqrt(u * u + v * v), phi = std::atan2(v, u);
        double y = drop - 0.15 * (1.0 - rho * rho / 2.0);
        const double limit = 0.97 * funnel_radius(y) * (1.0 + 0.06 * std::sin(8.0 * phi));
        double r = rho;
        if (rho > limit) {
          // Excess cloth goes up the wall; its fold height grows with the excess.
          r = limit;
          y += 0.9 * (rho - limit);
        }
        out[size_t(j) * res_ + i] = {float(r * std::cos(phi)), float(y), float(r * std::sin(phi))};
      }
    for (uint32_t ring = 0; ring < rings_; ++ring)
      for (uint32_t s = 0; s <= segments_; ++s) {
        const double y = -1.2 * ring / (rings_ - 1);
        const double a = 6.283185307179586 * s / segments_;
        const double r = funnel_radius(y);
        out[funnel_base_ + size_t(ring) * (segments_ + 1) + s] = {float(r * std::cos(a)), float(y),
                                                                  float(r * std::sin(a))};
      }
  }

 private:
  uint32_t res_ = 48, segments_ = 48, rings_ = 8, funnel_base_ = 0;
};

}  // namespace

const std::vector<std::string>& generator_names() {
  static const std::vector<std::string> names = {"soup", "cloth-wave", "funnel"};
  return names;
}

std::unique_ptr<FrameSource> make_generator(const std::string& name, const nlohmann::json& params) {
  Params p(name, params);
  if (name == "soup") return std::make_unique<SoupSource>(p);
  if (name == "cloth-wave") return std::make_unique<ClothWaveSource>(p);
  if (name == "funnel") return std::make_unique<FunnelSource>(p);
  std::string list;
  for (const auto& n : generator_names()) list += (list.empty() ? "" : ", ") + n;
  fail("unknown generator '" + name + "' (known: " + list + ")");
}

}  // namespace cdb
