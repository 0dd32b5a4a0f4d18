#include "scenes/generators/colliders.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdb::scene {
namespace {

struct Vec2 {
  double x, y;
};
Vec2 sub(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
double dot2(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }

// Closest point of the profile polyline to q (in meridian coordinates rho, y).
struct Closest {
  Vec2 point;
  Vec2 normal;     // left normal of the closest edge (unit), averaged at joints
  bool free_end;   // the closest point is the polyline's first or last point
  double distance;
};

Closest closest_on_profile(const Profile& prof, Vec2 q) {
  Closest best{{0, 0}, {0, 1}, false, std::numeric_limits<double>::infinity()};
  const size_t edges = prof.size() - 1;
  for (size_t e = 0; e < edges; ++e) {
    const Vec2 a{prof[e].rho, prof[e].y}, b{prof[e + 1].rho, prof[e + 1].y};
    const Vec2 ab = sub(b, a);
    const double len2 = dot2(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot2(sub(q, a), ab) / len2, 0.0, 1.0) : 0.0;
    const Vec2 p{a.x + t * ab.x, a.y + t * ab.y};
    const double d = std::sqrt(dot2(sub(q, p), sub(q, p)));
    if (d >= best.distance) continue;
    const double len = std::sqrt(len2);
    Vec2 n = len > 0 ? Vec2{-ab.y / len, ab.x / len} : Vec2{0, 1};
    // At a joint between two edges the normal is the mean of both, so a vertex in the
    // corner is pushed out of it rather than along one edge into the other.
    const bool at_start = t == 0.0, at_end = t == 1.0;
    const size_t other = at_start && e > 0 ? e - 1 : at_end && e + 1 < edges ? e + 1 : e;
    if (other != e) {
      const Vec2 c{prof[other].rho, prof[other].y}, d2{prof[other + 1].rho, prof[other + 1].y};
      const Vec2 cd = sub(d2, c);
      const double l = std::sqrt(dot2(cd, cd));
      if (l > 0) {
        n = {n.x - cd.y / l, n.y + cd.x / l};
        const double nl = std::sqrt(dot2(n, n));
        n = nl > 0 ? Vec2{n.x / nl, n.y / nl} : Vec2{-ab.y / len, ab.x / len};
      }
    }
    best = {p, n, (at_start && e == 0) || (at_end && e + 1 == edges), d};
  }
  return best;
}

// Point-in-polygon (crossing count) for the profile closed along the axis.
bool inside_profile(const Profile& prof, Vec2 q) {
  bool in = false;
  const size_t n = prof.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a{prof[i].rho, prof[i].y}, b{prof[j].rho, prof[j].y};
    if ((a.y > q.y) != (b.y > q.y) && q.x < (b.x - a.x) * (q.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

// Meridian frame of p about the collider's axis: unit radial direction and 2D coordinates.
struct Meridian {
  dvec3 radial;
  Vec2 q;
};

Meridian meridian(const RevolvedCollider& s, dvec3 p) {
  const dvec3 d = p - s.origin;
  const double rho = std::sqrt(d.x * d.x + d.z * d.z);
  const dvec3 radial = rho > 1e-12 ? dvec3{d.x / rho, 0, d.z / rho} : dvec3{1, 0, 0};
  return {radial, {rho, d.y}};
}

dvec3 to_world(const RevolvedCollider& s, const Meridian& m, Vec2 q) {
  return s.origin + q.x * m.radial + dvec3{0, q.y, 0};
}

}  // namespace

bool resolve(const SphereCollider& s, double thickness, dvec3& p, Contact& c) {
  const dvec3 d = p - s.center;
  const double r = s.radius + thickness, l2 = dot(d, d);
  if (l2 >= r * r) return false;
  const double l = std::sqrt(l2);
  c.normal = l > 1e-12 ? (1.0 / l) * d : dvec3{0, 1, 0};
  p = s.center + r * c.normal;
  c.surface_velocity = s.velocity + cross(s.spin, s.radius * c.normal);
  return true;
}

bool resolve(const CapsuleCollider& s, double thickness, dvec3& p, Contact& c) {
  const dvec3 ab = s.b - s.a;
  const double t = std::clamp(dot(p - s.a, ab) / std::max(dot(ab, ab), 1e-300), 0.0, 1.0);
  const dvec3 q = s.a + t * ab, d = p - q;
  const double r = s.radius + thickness, l2 = dot(d, d);
  if (l2 >= r * r) return false;
  const double l = std::sqrt(l2);
  c.normal = l > 1e-12 ? (1.0 / l) * d : normalized(cross(ab, dvec3{0, 0, 1}));
  p = q + r * c.normal;
  c.surface_velocity = {};
  return true;
}

bool resolve(const RevolvedCollider& s, double thickness, dvec3& p, int8_t& side, Contact& c) {
  const Meridian m = meridian(s, p);
  const Closest k = closest_on_profile(s.profile, m.q);
  Vec2 target;
  if (s.solid) {
    const bool in = inside_profile(s.profile, m.q);
    if (!in && k.distance >= thickness) return false;
    // Outward: away from the surface when outside, through it when inside.
    Vec2 out = k.distance > 1e-12 ? Vec2{(m.q.x - k.point.x) / k.distance, (m.q.y - k.point.y) / k.distance}
                                  : k.normal;
    if (in) out = {-out.x, -out.y};
    target = {k.point.x + thickness * out.x, k.point.y + thickness * out.y};
  } else {
    const Vec2 d = sub(m.q, k.point);
    const int8_t now = dot2(d, k.normal) >= 0 ? 1 : -1;
    if (k.free_end) {
      // Around a free end either side is fine; only keep the vertex off the edge.
      if (k.distance >= thickness) {
        side = now;
        return false;
      }
      const Vec2 out = k.distance > 1e-12 ? Vec2{d.x / k.distance, d.y / k.distance}
                                          : Vec2{side * k.normal.x, side * k.normal.y};
      target = {k.point.x + thickness * out.x, k.point.y + thickness * out.y};
    } else {
      // Crossing the shell away from its ends is a tunnelling step: undo it.
      if (now == side && k.distance >= thickness) return false;
      target = {k.point.x + side * thickness * k.normal.x, k.point.y + side * thickness * k.normal.y};
    }
  }
  // A target radius below zero (pushed across the axis) lands on the far side by its sign.
  p = to_world(s, m, target);
  const dvec3 surface = to_world(s, m, k.point);
  c.normal = normalized(p - surface);
  c.surface_velocity = s.velocity;
  return true;
}

int8_t shell_side(const RevolvedCollider& s, dvec3 p) {
  const Meridian m = meridian(s, p);
  const Closest k = closest_on_profile(s.profile, m.q);
  return dot2(sub(m.q, k.point), k.normal) >= 0 ? 1 : -1;
}

}  // namespace cdb::scene

namespace cdb::scene {
namespace {

// Closest point of triangle abc to p as barycentric weights (Ericson, Real-Time Collision
// Detection, 5.1.5).
dvec3 closest_weights(dvec3 p, dvec3 a, dvec3 b, dvec3 c) {
  const dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const dvec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const dvec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

dvec3 blend(const std::vector<dvec3>& x, const Tri& t, dvec3 w) { return w.x * x[t.v0] + w.y * x[t.v1] + w.z * x[t.v2]; }

}  // namespace

MeshSurface::MeshSurface(std::shared_ptr<const std::vector<Tri>> faces, std::vector<dvec3> positions,
                         std::vector<dvec3> velocities, double reach)
    : faces_(std::move(faces)), x_(std::move(positions)), v_(std::move(velocities)), reach_(reach) {
  const std::vector<Tri>& f = *faces_;
  n_.resize(f.size());
  centre_.resize(f.size());
  radius_.resize(f.size());
  dvec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
  double edges = 0;
  for (size_t i = 0; i < f.size(); ++i) {
    const dvec3 a = x_[f[i].v0], b = x_[f[i].v1], c = x_[f[i].v2];
    n_[i] = normalized(cross(b - a, c - a));
    centre_[i] = (1.0 / 3.0) * (a + b + c);
    radius_[i] = std::max({length(a - centre_[i]), length(b - centre_[i]), length(c - centre_[i])});
    edges += length(b - a) + length(c - b) + length(a - c);
    for (const dvec3& q : {a, b, c}) {
      lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
      hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
    }
  }
  if (f.empty()) return;
  // Cells about two mean edges wide (and no narrower than the reach): a few faces each.
  cell_ = std::max(2.0 * edges / (3.0 * double(f.size())), reach_);
  lo_ = lo - dvec3{reach_, reach_, reach_};
  const dvec3 extent = hi - lo + 2.0 * dvec3{reach_, reach_, reach_};
  const double e[3] = {extent.x, extent.y, extent.z};
  for (int k = 0; k < 3; ++k) dims_[k] = std::max<int64_t>(1, int64_t(std::ceil(e[k] / cell_)));
  auto cell_of = [&](double v, int k) {
    const double o[3] = {lo_.x, lo_.y, lo_.z};
    return std::clamp<int64_t>(int64_t(std::floor((v - o[k]) / cell_)), 0, dims_[k] - 1);
  };
  const size_t cells = size_t(dims_[0] * dims_[1] * dims_[2]);
  // Two passes over the faces' cell ranges: count, then fill (CSR, faces in order per cell).
  cell_start_.assign(cells + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<uint32_t> fill;
    if (pass == 1) {
      for (size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
      cell_faces_.resize(cell_start_[cells]);
      fill.assign(cell_start_.begin(), cell_start_.end() - 1);
    }
    for (uint32_t i = 0; i < f.size(); ++i) {
      const dvec3 a = x_[f[i].v0], b = x_[f[i].v1], c = x_[f[i].v2];
      const double flo[3] = {std::min({a.x, b.x, c.x}) - reach_, std::min({a.y, b.y, c.y}) - reach_,
                             std::min({a.z, b.z, c.z}) - reach_};
      const double fhi[3] = {std::max({a.x, b.x, c.x}) + reach_, std::max({a.y, b.y, c.y}) + reach_,
                             std::max({a.z, b.z, c.z}) + reach_};
      for (int64_t z = cell_of(flo[2], 2); z <= cell_of(fhi[2], 2); ++z)
        for (int64_t y = cell_of(flo[1], 1); y <= cell_of(fhi[1], 1); ++y)
          for (int64_t x = cell_of(flo[0], 0); x <= cell_of(fhi[0], 0); ++x) {
            const size_t cell = size_t((z * dims_[1] + y) * dims_[0] + x);
            if (pass == 0) ++cell_start_[cell + 1];
            else cell_faces_[fill[cell]++] = i;
          }
    }
  }
}

bool MeshSurface::nearest(dvec3 p, uint32_t& face, dvec3& weights, double& distance) const {
  if (cell_faces_.empty()) return false;
  const double q[3] = {(p.x - lo_.x) / cell_, (p.y - lo_.y) / cell_, (p.z - lo_.z) / cell_};
  int64_t c[3];
  for (int k = 0; k < 3; ++k) {
    if (!(q[k] >= 0) || q[k] >= double(dims_[k])) return false;
    c[k] = int64_t(q[k]);
  }
  const size_t cell = size_t((c[2] * dims_[1] + c[1]) * dims_[0] + c[0]);
  distance = reach_;
  bool found = false;
  for (uint32_t k = cell_start_[cell]; k < cell_start_[cell + 1]; ++k) {
    const uint32_t i = cell_faces_[k];
    // A face whose bounding sphere is no nearer than the best so far cannot be nearer.
    if (length(p - centre_[i]) - radius_[i] >= distance) continue;
    const Tri& t = (*faces_)[i];
    const dvec3 w = closest_weights(p, x_[t.v0], x_[t.v1], x_[t.v2]);
    const double d = length(p - blend(x_, t, w));
    // Ties go to the lower face index (cells list faces in order): the same answer on
    // every run.
    if (d < distance) distance = d, face = i, weights = w, found = true;
  }
  return found;
}

bool resolve(const MeshCollider& m, double thickness, dvec3& p, Contact& c) {
  uint32_t face;
  dvec3 w;
  double distance;
  if (!m.surface || !m.surface->nearest(p, face, w, distance)) return false;
  const Tri& t = m.surface->faces()[face];
  const dvec3 n = m.surface->normals()[face];
  const dvec3 q = blend(m.surface->positions(), t, w);
  const double side = dot(p - q, n);
  if (side >= thickness || side < -m.depth) return false;
  p += (thickness - side) * n;
  c.normal = n;
  c.surface_velocity = blend(m.surface->velocities(), t, w);
  return true;
}

}  // namespace cdb::scene
