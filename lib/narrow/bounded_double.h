#pragma once
// A double carried with what bounds its rounding error: the filter of the proximity
// predicates (proximity.h). A polynomial is evaluated once in this type and once, only where
// the filter cannot decide its sign, exactly (wide_int.h).
//
// The bound (a running form of the classic forward error analysis of +, -, * trees). Leaves
// are float inputs x (exact in double: roundings 0, magnitude |x|) or differences of two
// float inputs (one rounding: roundings 1, magnitude |fl(x - y)|). For y +- z the roundings
// are max(k_y, k_z) + 1 and the magnitude fl(M_y + M_z); for y * z they are k_y + k_z + 1
// and fl(M_y * M_z). Let E be the exact value of the expression, V the exact value of the
// same tree over the exact |leaf| values with - read as + (so |E| <= V), k its roundings and
// M its computed magnitude. With round to nearest and every operation rounding with relative
// error at most eps = 2^-53:
//   (1) |fl(E) - E| <= ((1 + eps)^k - 1) V, by induction: a sum adds the errors of its terms
//       and eps |fl(y) +- fl(z)| <= eps (1 + eps)^(k - 1) V; a product's error is
//       |fl(y) fl(z) - y z| + eps |fl(y) fl(z)| <= ((1 + eps)^(k_y + k_z + 1) - 1) V_y V_z.
//       A leaf difference rounds once: |fl(x - y) - (x - y)| <= eps |x - y|.
//   (2) M >= (1 - eps)^k V: every operation of the magnitude tree adds or multiplies
//       nonnegative values and loses at most a factor (1 - eps).
// So |fl(E) - E| <= ((1 + eps)^k - 1) (1 - eps)^-k M <= k eps e^(3 k eps) M < 2 k eps (1 - eps) M
// for k eps < 2^-40, and bound() = fl(2 k eps M) >= 2 k eps (1 - eps) M is a valid bound.
// A compiler fusing a product into a sum or difference (FMA contraction; nvcc does by default)
// removes the product's rounding, which only lowers both sides of (1) and (2).
//
// Why every operation rounds relatively (no underflow, no overflow): the proximity
// polynomials are homogeneous of degree g <= 6 in the leaves (a difference or d counts 1).
// Floats are multiples of 2^-149, below 2^128. By induction every computed node of degree g
// is 0 or a multiple of 2^(-149 g) (rounding a multiple of 2^-q to 53 bits keeps it one,
// because the result's ulp is either smaller than the value's exact bits need, so nothing
// is lost, or a power of two >= 2^-q), so a nonzero one is at least 2^-894, and at most
// 2^(129 g + 8) <= 2^782: inside the normal range of doubles, and bound() of a nonzero M is
// at least 2^-947, still normal.
#include <cmath>

#include "cdbench/core/hd.h"
#include "cdbench/narrow/predicates.h"

namespace cdb {

struct BoundedDouble {
  double value;      // fl(E)
  double magnitude;  // M
  int roundings;     // k

  CDB_HD_INLINE static BoundedDouble of_float(float x) { return {double(x), fabs(double(x)), 0}; }
  CDB_HD_INLINE static BoundedDouble of_difference(float x, float y) {
    const double v = double(x) - double(y);
    return {v, fabs(v), 1};
  }
  // |fl(E) - E| <= bound() (file comment).
  CDB_HD_INLINE double bound() const { return double(2 * roundings) * kEpsilon * magnitude; }
};

CDB_HD_INLINE int max_roundings(int a, int b) { return a < b ? b : a; }

CDB_HD_INLINE BoundedDouble operator+(const BoundedDouble& a, const BoundedDouble& b) {
  return {a.value + b.value, a.magnitude + b.magnitude, max_roundings(a.roundings, b.roundings) + 1};
}
CDB_HD_INLINE BoundedDouble operator-(const BoundedDouble& a, const BoundedDouble& b) {
  return {a.value - b.value, a.magnitude + b.magnitude, max_roundings(a.roundings, b.roundings) + 1};
}
CDB_HD_INLINE BoundedDouble operator*(const BoundedDouble& a, const BoundedDouble& b) {
  return {a.value * b.value, a.magnitude * b.magnitude, a.roundings + b.roundings + 1};
}

}  // namespace cdb
