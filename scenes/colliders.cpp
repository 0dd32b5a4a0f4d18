#include "colliders.h"

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
