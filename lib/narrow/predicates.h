#pragma once
// Robust orientation predicates on float coordinates: a filtered double evaluation and,
// where the filter cannot decide, an exact one (Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates", DCG 18, 1997).
//
// orient3d(a, b, c, d) = sign of ((b - a) x (c - a)) . (d - a): positive when d lies on the
// side the normal of (a, b, c) points to (the convention of Guigue and Devillers'
// triangle test). This is minus Shewchuk's orient3d(a, b, c, d) = det[a-d; b-d; c-d].
// orient2d(a, b, c) = sign of (b - a) x (c - a): positive when a, b, c turn counterclockwise
// (Shewchuk's orient2d).
//
// Why the exact path does not use differences of coordinates: a difference of two floats
// is not always a double (1e30f - 1e-30f needs about 200 bits). Both determinants are
// instead expanded over the raw coordinates (the 4x4 / 3x3 determinant with a column of
// ones): orient2d is a sum of 6 products of two floats, orient3d a sum of 24 products of
// three. A product of two floats (24-bit significands) is exact in a double (48 bits); a
// product of three is exact as two doubles (two_product). Magnitudes stay inside the
// normal double range: floats lie in [2^-149, 2^128), so a nonzero product of three lies in
// [2^-447, 2^384) and its rounding error term above 2^-500, far from under- or overflow.
// The sign of the sum is then that of an expansion (expansion.h).
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"
#include "cdbench/narrow/expansion.h"

namespace cdb {

// Unit roundoff of binary64 (Shewchuk's epsilon): |fl(x op y) - x op y| <= kEpsilon |x op y|.
inline constexpr double kEpsilon = 1.0 / 9007199254740992.0;  // 2^-53

// A point of a coordinate plane (a 3D point with one axis dropped).
struct point2f {
  float x, y;
};

CDB_HD_INLINE float coordinate(const vec3f& p, int axis) { return axis == 0 ? p.x : axis == 1 ? p.y : p.z; }

// p without coordinate `axis`, the other two in cyclic order (x drops to (y, z), y to (z, x),
// z to (x, y)), so the projection keeps the orientation of the normal's `axis` component.
CDB_HD_INLINE point2f drop_axis(const vec3f& p, int axis) {
  return axis == 0 ? point2f{p.y, p.z} : axis == 1 ? point2f{p.z, p.x} : point2f{p.x, p.y};
}

// The exact evaluations run only where a filter cannot decide. Out of line in device code:
// inlined into every filter of triangles_intersect they made its kernel about 400K lines of PTX
// and its test file minutes of ptxas.
CDB_HD_CALL int orient2d_exact(point2f a, point2f b, point2f c) {
  const double ax = a.x, ay = a.y, bx = b.x, by = b.y, cx = c.x, cy = c.y;
  // det [[ax ay 1] [bx by 1] [cx cy 1]]; each product of two floats is exact in a double.
  const double terms[6] = {ax * by, -ax * cy, -ay * bx, ay * cx, bx * cy, -by * cx};
  return sign_of_exact_sum(terms, 6);
}

// Filter: Shewchuk's orient2d stage A, evaluated in double on the float inputs.
// Why the bound is valid: his analysis bounds the error of this expression by
// (3 + 16 eps) eps (|detleft| + |detright|), assuming only that every operation rounds with
// relative error at most eps. Here that holds: inputs are floats, so each difference is a
// double of magnitude 0 or in [2^-149, 2^129] and each product 0 or in [2^-298, 2^258]: no
// overflow, no underflow. We use 4 eps, larger than (3 + 16 eps) eps. A compiler fusing a
// product into the subtraction (nvcc does by default) removes one rounding, which only
// lowers the error. Inside the bound (det == 0 included) the exact evaluation decides.
CDB_HD_INLINE int orient2d(point2f a, point2f b, point2f c) {
  const double detleft = (double(a.x) - c.x) * (double(b.y) - c.y);
  const double detright = (double(a.y) - c.y) * (double(b.x) - c.x);
  const double det = detleft - detright;
  const double bound = 4.0 * kEpsilon * (fabs(detleft) + fabs(detright));
  if (det > bound) return 1;
  if (det < -bound) return -1;
  return orient2d_exact(a, b, c);
}

namespace detail {

// Appends the exact value of sign * (x * y * z) as two doubles.
CDB_HD_INLINE void push_triple_product(double* terms, int& n, double sign, float x, float y, float z) {
  double p, e;
  two_product(sign * (double(x) * double(y)), double(z), p, e);
  terms[n++] = p;
  terms[n++] = e;
}

// Appends sign * det[p; q; r] (rows are points) as 12 doubles.
CDB_HD_INLINE void push_det3(double* terms, int& n, double sign, const vec3f& p, const vec3f& q, const vec3f& r) {
  push_triple_product(terms, n, sign, p.x, q.y, r.z);
  push_triple_product(terms, n, -sign, p.x, q.z, r.y);
  push_triple_product(terms, n, -sign, p.y, q.x, r.z);
  push_triple_product(terms, n, sign, p.y, q.z, r.x);
  push_triple_product(terms, n, sign, p.z, q.x, r.y);
  push_triple_product(terms, n, -sign, p.z, q.y, r.x);
}

}  // namespace detail

CDB_HD_CALL int orient3d_exact(const vec3f& a, const vec3f& b, const vec3f& c, const vec3f& d) {
  // det[b-a; c-a; d-a] = -det4[a 1; b 1; c 1; d 1]; expanding the 4x4 determinant along its
  // column of ones gives det3(b,c,d) - det3(a,c,d) + det3(a,b,d) - det3(a,b,c).
  double terms[48];
  int n = 0;
  detail::push_det3(terms, n, 1.0, b, c, d);
  detail::push_det3(terms, n, -1.0, a, c, d);
  detail::push_det3(terms, n, 1.0, a, b, d);
  detail::push_det3(terms, n, -1.0, a, b, c);
  return sign_of_exact_sum(terms, n);
}

// Filter: Shewchuk's orient3d stage A (differences from d, cofactor expansion, permanent),
// which computes det[a-d; b-d; c-d] = -orient3d(a, b, c, d).
// Why the bound is valid: Shewchuk bounds the error of exactly this evaluation by
// (7 + 56 eps) eps * permanent, assuming every operation rounds with relative error at most
// eps. With float inputs that holds: every difference is 0 or in [2^-149, 2^129], every
// product of two 0 or in [2^-298, 2^258], of three 0 or in [2^-447, 2^387], sums of these
// stay below 2^390; nothing overflows and no product underflows (additions of doubles are
// exact when their result is tiny, so they cannot underflow with an error). We use 8 eps,
// larger than (7 + 56 eps) eps; products fused into sums by the compiler only remove
// roundings. Inside the bound (det == 0 included) the exact evaluation decides.
CDB_HD_INLINE int orient3d(const vec3f& a, const vec3f& b, const vec3f& c, const vec3f& d) {
  const double adx = double(a.x) - d.x, ady = double(a.y) - d.y, adz = double(a.z) - d.z;
  const double bdx = double(b.x) - d.x, bdy = double(b.y) - d.y, bdz = double(b.z) - d.z;
  const double cdx = double(c.x) - d.x, cdy = double(c.y) - d.y, cdz = double(c.z) - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double permanent = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) + (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                           (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
  const double bound = 8.0 * kEpsilon * permanent;
  if (det > bound) return -1;
  if (det < -bound) return 1;
  return orient3d_exact(a, b, c, d);
}

}  // namespace cdb
