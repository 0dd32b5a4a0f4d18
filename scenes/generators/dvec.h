#pragma once
// Double-precision 3-vectors and rigid poses for the scene simulations. Double so that
// long simulations do not drift; frames are converted to float only on output.
#include <cmath>

namespace cdb::scene {

struct dvec3 {
  double x = 0, y = 0, z = 0;
};

inline dvec3 operator+(dvec3 a, dvec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline dvec3 operator-(dvec3 a, dvec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline dvec3 operator-(dvec3 a) { return {-a.x, -a.y, -a.z}; }
inline dvec3 operator*(double s, dvec3 a) { return {s * a.x, s * a.y, s * a.z}; }
inline dvec3 operator*(dvec3 a, double s) { return {s * a.x, s * a.y, s * a.z}; }
inline dvec3& operator+=(dvec3& a, dvec3 b) { return a = a + b; }
inline dvec3& operator-=(dvec3& a, dvec3 b) { return a = a - b; }
inline double dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline dvec3 cross(dvec3 a, dvec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(dvec3 a) { return std::sqrt(dot(a, a)); }
inline dvec3 normalized(dvec3 a) {
  const double l = length(a);
  return l > 0 ? (1.0 / l) * a : dvec3{};
}

// A rigid placement: x -> R x + t.
struct Pose {
  double r[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  dvec3 t;

  dvec3 rotate(dvec3 p) const {
    return {r[0][0] * p.x + r[0][1] * p.y + r[0][2] * p.z, r[1][0] * p.x + r[1][1] * p.y + r[1][2] * p.z,
            r[2][0] * p.x + r[2][1] * p.y + r[2][2] * p.z};
  }
  dvec3 apply(dvec3 p) const { return rotate(p) + t; }
};

// Rotation by `angle` radians about the unit `axis` (Rodrigues).
inline Pose rotation(dvec3 axis, double angle, dvec3 translation = {}) {
  const double c = std::cos(angle), s = std::sin(angle), k = 1 - c;
  const double x = axis.x, y = axis.y, z = axis.z;
  Pose p;
  p.r[0][0] = c + x * x * k, p.r[0][1] = x * y * k - z * s, p.r[0][2] = x * z * k + y * s;
  p.r[1][0] = y * x * k + z * s, p.r[1][1] = c + y * y * k, p.r[1][2] = y * z * k - x * s;
  p.r[2][0] = z * x * k - y * s, p.r[2][1] = z * y * k + x * s, p.r[2][2] = c + z * z * k;
  p.t = translation;
  return p;
}

}  // namespace cdb::scene
