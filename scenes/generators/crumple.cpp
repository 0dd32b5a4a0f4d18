// A square sheet squeezed towards its middle and churned onto itself.
//
// The sheet is carried by a smooth velocity field over the run (scene time 0 to 1; frame 0
// at `start`, so the sheet is already gathered a little): a squeeze drawing every point
// towards the vertical axis, to `squeeze` of its distance by the end (folds and vortices
// keep the sheet wider: at 0.4 it ends about half its width, its area within about 15% of
// the flat sheet's, as cloth's); folds lifting it out of its plane where the squeeze
// gathers it; and vortex tubes, most with horizontal axes, that roll the folds over onto
// the sheet. The flow of a smooth field is one-to-one, so the smooth sheet folds onto itself
// more and more but never passes through itself, as a simulation with self-collision keeps
// it; only the mesh's flat triangles can cut each other where folds touch, fewer the finer
// the mesh (none at 256x256). Parts of the sheet far apart at frame 0 end up lying on each
// other: a hierarchy built on frame 0 goes stale while the pairs grow.
#include "scenes/generators/crumple.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "scenes/generators/cloth_scene.h"
#include "cdbench/core/error.h"
#include "scenes/generators/dvec.h"
#include "scenes/generators/rng.h"
#include "scenes/generators/stepped_source.h"

namespace cdb::scene {
namespace {

constexpr double kCrumpleTurn = 2 * 3.141592653589793;

// Material within about `radius` of the line through `centre` along `axis` turns about it
// at up to `rate` radians per unit of scene time, the rate falling off as a Gaussian of
// the distance, so the sheet is wound into spirals rather than turned rigidly.
struct Vortex {
  dvec3 centre, axis;
  double radius, rate;
};

// One fold of the lift: vertical speed amplitude * sin(kx * x + kz * z + phase), in the
// sheet's own coordinates (undone squeeze), so each fold stays on the same part of the sheet.
struct Fold {
  double kx, kz, phase, amplitude;
};

class CrumpleField {
 public:
  CrumpleField(double squeeze, double lift, double churn, uint32_t vortices, uint64_t seed)
      : rate_(-std::log(squeeze)) {
    Rng rng{seed};
    for (int f = 0; f < 6; ++f) {
      // Wavelengths a tenth to a third of the sheet, in every direction.
      const double angle = kCrumpleTurn * rng.uniform(), k = kCrumpleTurn / (0.1 + 0.23 * rng.uniform());
      folds_.push_back({k * std::cos(angle), k * std::sin(angle), kCrumpleTurn * rng.uniform(),
                        lift * 0.03 * (0.5 + rng.uniform())});
    }
    for (uint32_t v = 0; v < vortices; ++v) {
      const double angle = kCrumpleTurn * rng.uniform();
      const double tilt = 0.3 * rng.symmetric();
      const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
      vortices_.push_back({{0.4 * rng.symmetric(), 0.0, 0.4 * rng.symmetric()},
                           normalized({std::cos(angle), tilt, std::sin(angle)}),
                           0.08 + 0.08 * rng.uniform(),
                           sign * churn * kCrumpleTurn * (0.5 + 0.5 * rng.uniform())});
    }
    // The churn: one swirl about the vertical through the middle, turning the gathered
    // folds over each other.
    vortices_.push_back({{0, 0, 0}, {0, 1, 0}, 0.25, churn * 0.5 * kCrumpleTurn});
  }

  dvec3 at(dvec3 p, double t) const {
    const double shrink = std::exp(-rate_ * t);
    dvec3 u{-rate_ * p.x, 0.0, -rate_ * p.z};
    const double sx = p.x / shrink, sz = p.z / shrink;
    for (const Fold& f : folds_) u.y += f.amplitude * std::sin(f.kx * sx + f.kz * sz + f.phase);
    for (const Vortex& v : vortices_) {
      // The vortices ride the squeeze, each on the same part of the sheet.
      const dvec3 c{v.centre.x * shrink, v.centre.y, v.centre.z * shrink};
      const dvec3 d = p - c;
      const dvec3 r = d - dot(d, v.axis) * v.axis;
      const double spin = v.rate * std::exp(-dot(r, r) / (v.radius * v.radius));
      u += spin * cross(v.axis, r);
    }
    return u;
  }

 private:
  double rate_;
  std::vector<Fold> folds_;
  std::vector<Vortex> vortices_;
};

class CrumpleSource final : public SteppedSource<std::vector<dvec3>> {
 public:
  explicit CrumpleSource(Params& p) {
    const uint32_t res = p.count32("res", 256, 2, 20000);
    frames_ = p.count32("frames", 40, 1, 100000);
    const double squeeze = p.number("squeeze", 0.4);
    const double lift = p.number("lift", 1.0);
    const double churn = p.number("churn", 0.9);
    const uint32_t vortices = p.count32("vortices", 8, 0, 1000);
    start_time_ = p.number("start", 0.3);
    steps_ = p.count32("steps", 160, 1, 1000000);
    const uint64_t seed = p.count_in("seed", 1, 0, scene::kLargestExactCount);
    p.finish();
    if (!(squeeze > 0 && squeeze <= 1)) fail("generator 'crumple', parameter 'squeeze': must be in (0, 1]");
    if (!(lift >= 0 && lift <= 100)) fail("generator 'crumple', parameter 'lift': must be between 0 and 100");
    if (!(churn >= 0 && churn <= 100)) fail("generator 'crumple', parameter 'churn': must be between 0 and 100");
    if (!(start_time_ >= 0 && start_time_ < 1)) fail("generator 'crumple', parameter 'start': must be in [0, 1)");
    field_.emplace(squeeze, lift, churn, vortices, seed);
    const double h = 1.0 / (res - 1);
    std::vector<Tri> faces;
    cloth_grid(res, res, {-0.5, 0, -0.5}, {h, 0, 0}, {0, 0, h}, flat_, faces);
    topology_.faces = std::move(faces);
    topology_.num_vertices = uint32_t(flat_.size());
    char text[64];
    std::snprintf(text, sizeof text, "%g%%", 100 * squeeze);
    description_ = "crumple: " + std::to_string(res) + "x" + std::to_string(res) + " sheet (" +
                   std::to_string(topology_.faces.size()) + " triangles) squeezed (every point drawn to " + text +
                   " of its distance from the middle) and churned onto itself, " + std::to_string(frames_) + " frames";
  }

 private:
  // Frame 0 at `start`, the last at the end of the run.
  double time_of(uint32_t k) const {
    return start_time_ + (1 - start_time_) * (frames_ > 1 ? double(k) / (frames_ - 1) : 0.0);
  }

  std::vector<dvec3> first() const override {
    std::vector<dvec3> x = flat_;
    carry(x, 0.0, time_of(0));
    return x;
  }
  void advance(std::vector<dvec3>& x, uint32_t from) const override { carry(x, time_of(from), time_of(from + 1)); }
  void write(const std::vector<dvec3>& x, std::vector<vec3d>& out) const override {
    out.resize(x.size());
    for (size_t v = 0; v < x.size(); ++v) out[v] = {x[v].x, x[v].y, x[v].z};
  }

  // Classic Runge-Kutta from t0 to t1, in steps no longer than 1 / `steps`, so that a
  // scene of fewer frames ends where the full one does; every vertex on its own, so the
  // result does not depend on the thread count.
  void carry(std::vector<dvec3>& x, double t0, double t1) const {
    const uint32_t steps = uint32_t(std::ceil((t1 - t0) * steps_ - 1e-9));
    if (steps == 0) return;
    const double h = (t1 - t0) / steps;
    const CrumpleField& f = *field_;
    const int64_t n = int64_t(x.size());
#pragma omp parallel for schedule(static)
    for (int64_t v = 0; v < n; ++v) {
      dvec3 p = x[v];
      for (uint32_t s = 0; s < steps; ++s) {
        const double t = t0 + s * h;
        const dvec3 k1 = f.at(p, t);
        const dvec3 k2 = f.at(p + (0.5 * h) * k1, t + 0.5 * h);
        const dvec3 k3 = f.at(p + (0.5 * h) * k2, t + 0.5 * h);
        const dvec3 k4 = f.at(p + h * k3, t + h);
        p += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      }
      x[v] = p;
    }
  }

  uint32_t steps_ = 160;
  double start_time_ = 0.3;
  std::optional<CrumpleField> field_;
  std::vector<dvec3> flat_;
};

}  // namespace

std::unique_ptr<FrameSource> make_crumple(Params& p) { return std::make_unique<CrumpleSource>(p); }

}  // namespace cdb::scene
