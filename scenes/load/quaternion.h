#pragma once
// Rotations as unit quaternions in double, interpolated along the shorter arc: the rigid
// motions' keys (io/rigid_mesh.h) and animated files' rotation keys (io/animated_mesh.h).
// In double because float's acos (assimp's own slerp) loses about 1e-4 rad near small
// angles between keys.
#include <algorithm>
#include <cmath>

namespace cdb {

struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

// Normalised, also at f = 0 or 1: keys written with few digits are not quite unit.
inline Quat slerp(Quat a, Quat b, double f) {
  double cosine = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (cosine < 0) cosine = -cosine, b = {-b.w, -b.x, -b.y, -b.z};
  double ka = 1 - f, kb = f;
  if (cosine < 1 - 1e-12) {
    const double angle = std::acos(std::min(cosine, 1.0)), sine = std::sin(angle);
    ka = std::sin((1 - f) * angle) / sine;
    kb = std::sin(f * angle) / sine;
  }
  const Quat q{ka * a.w + kb * b.w, ka * a.x + kb * b.x, ka * a.y + kb * b.y, ka * a.z + kb * b.z};
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}

}  // namespace cdb
