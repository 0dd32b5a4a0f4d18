#include "scenes/generators/n_body.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "cdbench/core/error.h"
#include "scenes/generators/dvec.h"
#include "scenes/generators/rigid_shapes.h"
#include "scenes/generators/rng.h"
#include "scenes/generators/stepped_source.h"

namespace cdb::scene {
namespace {

struct Body {
  dvec3 x, v, spin;  // centre of the bounding sphere, its velocity, angular velocity
  double q[4];       // orientation quaternion (w, x, y, z)
  double radius, inv_mass;
  uint32_t shape;  // 0: ball, 1: cone
};

Pose pose_of(const Body& b) {
  const double w = b.q[0], x = b.q[1], y = b.q[2], z = b.q[3];
  Pose p;
  p.r[0][0] = 1 - 2 * (y * y + z * z), p.r[0][1] = 2 * (x * y - w * z), p.r[0][2] = 2 * (x * z + w * y);
  p.r[1][0] = 2 * (x * y + w * z), p.r[1][1] = 1 - 2 * (x * x + z * z), p.r[1][2] = 2 * (y * z - w * x);
  p.r[2][0] = 2 * (x * z - w * y), p.r[2][1] = 2 * (y * z + w * x), p.r[2][2] = 1 - 2 * (x * x + y * y);
  p.t = b.x;
  return p;
}

// Simple rigid dynamics: gravity, walls and body-body contacts with restitution; each body
// collides as its bounding sphere (a cone too). Contacts are found in a uniform grid and
// resolved one pair at a time in index order, so runs are reproducible.
class NBody {
 public:
  NBody(std::vector<Body> bodies, dvec3 box, double gravity, double restitution, uint32_t passes)
      : b_(std::move(bodies)), half_(0.5 * box), gravity_(gravity), restitution_(restitution), passes_(passes) {
    for (const Body& b : b_) cell_ = std::max(cell_, 2 * b.radius);
  }

  void step(double dt, uint32_t substeps) {
    const double h = dt / substeps;
    for (uint32_t s = 0; s < substeps; ++s) {
      for (Body& b : b_) {
        b.v.y -= gravity_ * h;
        b.x += h * b.v;
        integrate_spin(b, h);
        walls(b);
      }
      // One sweep, after the walls, is the paper's N-body, whose bodies are mostly apart.
      // A pile needs several sweeps to settle, and each ends at the walls: bodies pressed
      // down by the pile must not sink through the floor.
      for (uint32_t pass = 0; pass < passes_; ++pass) {
        contacts();
        if (passes_ > 1)
          for (Body& b : b_) walls(b);
      }
    }
  }
  const std::vector<Body>& bodies() const { return b_; }

 private:
  static void integrate_spin(Body& b, double h) {
    // q += h/2 * (0, spin) * q, then renormalise.
    const double w = b.q[0], x = b.q[1], y = b.q[2], z = b.q[3];
    const double ox = b.spin.x, oy = b.spin.y, oz = b.spin.z, k = 0.5 * h;
    double q[4] = {w + k * (-ox * x - oy * y - oz * z), x + k * (ox * w + oy * z - oz * y),
                   y + k * (oy * w + oz * x - ox * z), z + k * (oz * w + ox * y - oy * x)};
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; ++i) b.q[i] = q[i] / n;
  }

  void walls(Body& b) const {
    double* x[3] = {&b.x.x, &b.x.y, &b.x.z};
    double* v[3] = {&b.v.x, &b.v.y, &b.v.z};
    const double half[3] = {half_.x, half_.y, half_.z};
    for (int a = 0; a < 3; ++a) {
      if (*x[a] - b.radius < -half[a]) {
        *x[a] = -half[a] + b.radius;
        if (*v[a] < 0) *v[a] = -restitution_ * *v[a];
      }
      if (*x[a] + b.radius > half[a]) {
        *x[a] = half[a] - b.radius;
        if (*v[a] > 0) *v[a] = -restitution_ * *v[a];
      }
    }
  }

  int64_t cell_of(double x, double half) const { return int64_t(std::floor((x + half) / cell_)); }

  void contacts() {
    const int64_t nx = cell_of(half_.x, half_.x) + 1, ny = cell_of(half_.y, half_.y) + 1,
                  nz = cell_of(half_.z, half_.z) + 1;
    auto key_of = [&](const Body& b) {
      const int64_t cx = std::clamp<int64_t>(cell_of(b.x.x, half_.x), 0, nx - 1);
      const int64_t cy = std::clamp<int64_t>(cell_of(b.x.y, half_.y), 0, ny - 1);
      const int64_t cz = std::clamp<int64_t>(cell_of(b.x.z, half_.z), 0, nz - 1);
      return (cz * ny + cy) * nx + cx;
    };
    order_.resize(b_.size());
    for (uint32_t i = 0; i < b_.size(); ++i) order_[i] = {key_of(b_[i]), i};
    std::sort(order_.begin(), order_.end());
    for (uint32_t i = 0; i < b_.size(); ++i) {
      const int64_t key = key_of(b_[i]);
      const int64_t cx = key % nx, cy = key / nx % ny, cz = key / (nx * ny);
      for (int64_t dz = -1; dz <= 1; ++dz)
        for (int64_t dy = -1; dy <= 1; ++dy)
          for (int64_t dx = -1; dx <= 1; ++dx) {
            const int64_t x = cx + dx, y = cy + dy, z = cz + dz;
            if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) continue;
            const int64_t k = (z * ny + y) * nx + x;
            auto it = std::lower_bound(order_.begin(), order_.end(), std::pair<int64_t, uint32_t>{k, 0});
            for (; it != order_.end() && it->first == k; ++it)
              if (it->second > i) collide(b_[i], b_[it->second]);
          }
    }
  }

  void collide(Body& a, Body& b) const {
    const dvec3 d = b.x - a.x;
    const double dist = length(d), overlap = a.radius + b.radius - dist;
    if (overlap <= 0 || dist < 1e-12) return;
    const dvec3 n = (1.0 / dist) * d;
    const double w = a.inv_mass + b.inv_mass;
    a.x -= (overlap * a.inv_mass / w) * n;
    b.x += (overlap * b.inv_mass / w) * n;
    const double vn = dot(b.v - a.v, n);
    if (vn >= 0) return;
    const double j = -(1 + restitution_) * vn / w;
    a.v -= (j * a.inv_mass) * n;
    b.v += (j * b.inv_mass) * n;
  }

  std::vector<Body> b_;
  dvec3 half_;
  double gravity_, restitution_, cell_ = 0;
  uint32_t passes_;
  std::vector<std::pair<int64_t, uint32_t>> order_;
};

class NBodySource final : public SteppedSource<NBody> {
 public:
  explicit NBodySource(Params& p) {
    const uint32_t balls = p.count32("spheres", 460, 0, 10000000);
    const uint32_t cones = p.count32("cones", 5, 0, 10000000);
    const uint32_t level = p.count32("sphere_level", 2, 0, 8);
    const uint32_t segments = p.count32("cone_segments", 32, 3, 100000);
    frames_ = p.count32("frames", 76, 1, 100000);
    warmup_ = p.count32("warmup", 10, 0, 100000);
    substeps_ = p.count32("substeps", 8, 1, 1000);
    const double speed = p.number("speed", 1.5);
    const double gravity = p.number("gravity", 2.0);
    const double restitution = p.number("restitution", 0.9);
    const double fill = p.number("fill", 0.15);
    const uint32_t passes = p.count32("passes", 1, 1, 1000);
    const uint64_t seed = p.count_in("seed", 1, 0, scene::kLargestExactCount);
    p.finish();
    if (!(restitution >= 0 && restitution <= 1)) fail("generator 'n-body', parameter 'restitution': must be between 0 and 1");
    if (!(fill > 0 && fill <= 0.5)) fail("generator 'n-body', parameter 'fill': must be in (0, 0.5]");
    if (!(std::abs(gravity) <= 1000)) fail("generator 'n-body', parameter 'gravity': must be between -1000 and 1000");

    // Ball radii 0.04..0.06; cones of base radius 0.06 and height 0.12. A cone's body origin
    // is the centre of its bounding sphere, on the axis at height c above the base.
    const double cone_r = 0.06, cone_h = 0.12, cone_c = (cone_h * cone_h - cone_r * cone_r) / (2 * cone_h);
    const double cone_bound = cone_h - cone_c;
    meshes_.push_back(icosphere(level, 1.0));
    meshes_.push_back(revolve(cone_profile(cone_r, cone_h), segments));
    for (dvec3& v : meshes_[1].vertices) v.y -= cone_c;

    Rng rng{seed};
    std::vector<Body> bodies;
    double volume = 0, largest = 0;
    for (uint32_t i = 0; i < balls + cones; ++i) {
      Body b{};
      b.shape = i < balls ? 0 : 1;
      b.radius = b.shape == 0 ? 0.04 + 0.02 * rng.uniform() : cone_bound;
      b.inv_mass = 1.0 / (b.radius * b.radius * b.radius);
      volume += 4.18879020478639 * b.radius * b.radius * b.radius;
      largest = std::max(largest, b.radius);
      const dvec3 axis = normalized({rng.normal(), rng.normal(), rng.normal()});
      const double angle = 3.141592653589793 * rng.uniform();
      b.q[0] = std::cos(angle / 2);
      b.q[1] = axis.x * std::sin(angle / 2), b.q[2] = axis.y * std::sin(angle / 2), b.q[3] = axis.z * std::sin(angle / 2);
      b.v = speed * dvec3{rng.normal(), rng.normal(), rng.normal()};
      b.spin = 3.0 * dvec3{rng.normal(), rng.normal(), rng.normal()};
      bodies.push_back(b);
    }
    // A cube holding the bodies at about `fill` volume fraction, on a lattice of sites two
    // largest radii apart taken in a seeded random order.
    const double spacing = 2.2 * std::max(largest, 1e-3);
    uint32_t side = uint32_t(std::ceil(std::cbrt(volume / fill) / spacing));
    while (uint64_t(side) * side * side < bodies.size()) ++side;
    const double box = side * spacing;
    std::vector<uint32_t> sites(uint64_t(side) * side * side);
    for (uint32_t i = 0; i < sites.size(); ++i) sites[i] = i;
    for (size_t i = sites.size(); i > 1; --i) std::swap(sites[i - 1], sites[rng.next() % i]);
    for (size_t i = 0; i < bodies.size(); ++i) {
      const uint32_t s = sites[i];
      bodies[i].x = {(s % side + 0.5) * spacing - box / 2, (s / side % side + 0.5) * spacing - box / 2,
                     (s / side / side + 0.5) * spacing - box / 2};
    }
    sim_.emplace(std::move(bodies), dvec3{box, box, box}, gravity, restitution, passes);

    for (const Body& b : sim_->bodies()) {
      append_faces(meshes_[b.shape], topology_.num_vertices, topology_.faces);
      topology_.num_vertices += uint32_t(meshes_[b.shape].vertices.size());
    }
    description_ = "n-body: " + std::to_string(balls) + " balls and " + std::to_string(cones) +
                   " cones in a box (" + std::to_string(topology_.faces.size()) + " triangles, " +
                   std::to_string(frames_) + " frames)";
  }

 private:
  NBody first() const override {
    NBody sim = *sim_;
    for (uint32_t f = 0; f < warmup_; ++f) sim.step(frame_time_, substeps_);
    return sim;
  }
  void advance(NBody& sim, uint32_t) const override { sim.step(frame_time_, substeps_); }
  void write(const NBody& sim, std::vector<vec3d>& out) const override {
    out.clear();
    out.reserve(topology_.num_vertices);
    for (const Body& b : sim.bodies()) {
      const Pose pose = pose_of(b);
      const double scale = b.shape == 0 ? b.radius : 1.0;
      for (const dvec3& v : meshes_[b.shape].vertices) {
        const dvec3 p = pose.apply(scale * v);
        out.push_back({p.x, p.y, p.z});
      }
    }
  }

  uint32_t warmup_ = 0, substeps_ = 1;
  double frame_time_ = 1.0 / 30.0;
  std::vector<RigidMesh> meshes_;  // unit ball, cone
  std::optional<NBody> sim_;       // initial state
};

}  // namespace

std::unique_ptr<FrameSource> make_n_body(Params& p) { return std::make_unique<NBodySource>(p); }

}  // namespace cdb::scene
