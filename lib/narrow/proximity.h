#pragma once
// Proximity of two closed triangles given by float vertices: is the Euclidean distance
// between them at most d? Exact for the float input (d a float too), degenerate triangles
// (segments, points, repeated vertices) included; no allocation, host and device.
//
// Distance. If the triangles intersect (triangle_intersect.h, exact) it is 0. Otherwise it
// is the least of the 6 vertex-triangle and 9 edge-edge distances. Why (a theorem for
// disjoint convex polytopes): take a closest pair of points x, y whose smallest supporting
// faces F, G (vertex, edge or the triangle) have the least total dimension. If
// dim F + dim G >= 3 (edge-triangle, triangle-triangle), then x - y, nonzero, is orthogonal
// to both faces, so a direction of F is parallel to G (or the planes are parallel), and
// moving x and y together along it keeps the distance until one reaches a lower face: a
// contradiction. So F, G is vertex-vertex, vertex-edge, vertex-triangle or edge-edge. The
// same holds for degenerate triangles, whose faces are their vertices and segments.
//
// Decision. dist <= d iff some candidate below is within d, each being the distance between
// a point of one triangle and a point of the other (so never below the true distance), and
// the closest pair being one of them (by the theorem, with x, y in the relative interiors):
//   vertex-vertex   |p - q|^2 <= d^2
//   vertex-edge     the foot of p on the line of [a, b] lies on the closed segment and
//                   |(p - a) x u|^2 <= d^2 |u|^2, u = b - a (u = 0: no candidate)
//   vertex-triangle the foot of p on the plane lies in the closed proper triangle and
//                   (n . (p - a))^2 <= d^2 |n|^2, n = (b - a) x (c - a)
//   edge-edge       m = u x v != 0 (not parallel: for parallel edges a closest pair with an
//                   end point exists) and the two closest points of the lines lie on the
//                   closed segments and (r . m)^2 <= d^2 |m|^2, r = q0 - p0
// Every condition is the sign of a homogeneous polynomial of degree <= 6 in coordinate
// differences and d. Each sign is decided exactly: evaluated in double with a proven error
// bound (bounded_double.h) and, where the value lies within the bound of 0, evaluated again
// in exact integer arithmetic (wide_int.h). No case is left undecided.
//
// Exact-path sizes (wide_int.h: coordinates and d in units of 2^-149 are below 2^277, so a
// difference is below 2^278): degree 2 (dot, cross components) < 2^558; degree 3 (r . m,
// n . w) < 2^838; degree 4 (triple products with m or n, |m|^2, |w x u|^2, d^2 |u|^2)
// < 2^1118; degree 6 (the squared plane and line distances and d^2 |m|^2, d^2 |n|^2)
// < 2^1677: 53 limbs; the largest product, (r . m)^2, multiplies two 27-limb numbers. The
// capacity of 56 limbs holds all of them.
#include <cfloat>

#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"
#include "cdbench/narrow/bounded_double.h"
#include "cdbench/narrow/expansion.h"
#include "cdbench/narrow/triangle_intersect.h"
#include "cdbench/narrow/wide_int.h"

namespace cdb {
namespace proximity {

template <class Num>
struct Vec3 {
  Num x, y, z;
};

template <class Num>
CDB_HD_INLINE Vec3<Num> difference(const vec3f& a, const vec3f& b) {
  return {Num::of_difference(a.x, b.x), Num::of_difference(a.y, b.y), Num::of_difference(a.z, b.z)};
}
template <class Num>
CDB_HD_INLINE Num dot(const Vec3<Num>& a, const Vec3<Num>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class Num>
CDB_HD_INLINE Vec3<Num> cross(const Vec3<Num>& a, const Vec3<Num>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class Num>
CDB_HD_INLINE Num squared_distance_bound(float d) {
  const Num dn = Num::of_float(d);
  return dn * dn;
}

// Sign (-1, 0, 1) of the polynomial f, exactly: the filter, then the exact evaluation.
template <class Polynomial>
CDB_HD_CALL int exact_sign(const Polynomial& f) {
  const BoundedDouble approx = f.template evaluate<BoundedDouble>();
  const double bound = approx.bound();
  if (approx.value > bound) return 1;
  if (approx.value < -bound) return -1;
  return f.template evaluate<WideInt>().sign;
}

// --- the polynomials ------------------------------------------------------------------------

// |p - q|^2 - d^2.
struct PointPointExcess {
  const vec3f &p, &q;
  float d;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> w = difference<Num>(p, q);
    return dot(w, w) - squared_distance_bound<Num>(d);
  }
};

// (p - a) . (b - a): positive when the foot of p on the line ab lies past a, towards b.
struct FootPastStart {
  const vec3f &p, &a, &b;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    return dot(difference<Num>(p, a), difference<Num>(b, a));
  }
};

// |(p - a) x u|^2 - d^2 |u|^2, u = b - a: the squared distance of p to the line ab, minus
// d^2, times |u|^2.
struct PointLineExcess {
  const vec3f &p, &a, &b;
  float d;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> u = difference<Num>(b, a), h = cross(difference<Num>(p, a), u);
    return dot(h, h) - squared_distance_bound<Num>(d) * dot(u, u);
  }
};

// ((b - a) x (p - a)) . n, n = (b - a) x (c - a): nonnegative when p lies on the inner side
// of the edge ab of triangle abc, measured in its plane (the foot of p is then on that side).
struct InsideEdge {
  const vec3f &p, &a, &b, &c;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> u = difference<Num>(b, a);
    return dot(cross(u, difference<Num>(p, a)), cross(u, difference<Num>(c, a)));
  }
};

// (n . (p - a))^2 - d^2 |n|^2, n = (b - a) x (c - a): the squared distance of p to the
// plane, minus d^2, times |n|^2.
struct PointPlaneExcess {
  const vec3f &p, &a, &b, &c;
  float d;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> n = cross(difference<Num>(b, a), difference<Num>(c, a));
    const Num h = dot(n, difference<Num>(p, a));
    return h * h - squared_distance_bound<Num>(d) * dot(n, n);
  }
};

// |m|^2, m = (p1 - p0) x (q1 - q0): zero iff the edges are parallel (or one is a point).
struct EdgesCrossNorm {
  const vec3f &p0, &p1, &q0, &q1;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> m = cross(difference<Num>(p1, p0), difference<Num>(q1, q0));
    return dot(m, m);
  }
};

// The parameter of the closest point of line p0 p1 to line q0 q1, times |m|^2:
// ((q0 - p0) x (q1 - q0)) . m, m = (p1 - p0) x (q1 - q0); with `from_end`, |m|^2 minus it.
// Both are nonnegative iff that point lies on the closed segment [p0, p1]. With the edges
// swapped it is the other line's parameter.
struct LineParameter {
  const vec3f &p0, &p1, &q0, &q1;
  bool from_end;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> u = difference<Num>(p1, p0), v = difference<Num>(q1, q0);
    const Vec3<Num> m = cross(u, v);
    const Num s = dot(cross(difference<Num>(q0, p0), v), m);
    return from_end ? dot(m, m) - s : s;
  }
};

// (r . m)^2 - d^2 |m|^2, r = q0 - p0, m = (p1 - p0) x (q1 - q0): the squared distance of
// the two lines, minus d^2, times |m|^2.
struct LineLineExcess {
  const vec3f &p0, &p1, &q0, &q1;
  float d;
  template <class Num>
  CDB_HD_INLINE Num evaluate() const {
    const Vec3<Num> m = cross(difference<Num>(p1, p0), difference<Num>(q1, q0));
    const Num h = dot(difference<Num>(q0, p0), m);
    return h * h - squared_distance_bound<Num>(d) * dot(m, m);
  }
};

// --- the candidates -------------------------------------------------------------------------

CDB_HD_INLINE bool point_point_within(const vec3f& p, const vec3f& q, float d) {
  return exact_sign(PointPointExcess{p, q, d}) <= 0;
}

// The foot of p on the line of [a, b] (a != b) is on the closed segment and within d.
CDB_HD_CALL bool point_segment_interior_within(const vec3f& p, const vec3f& a, const vec3f& b, float d) {
  if (narrow::same_point(a, b)) return false;
  return exact_sign(PointLineExcess{p, a, b, d}) <= 0 && exact_sign(FootPastStart{p, a, b}) >= 0 &&
         exact_sign(FootPastStart{p, b, a}) >= 0;
}

// The foot of p on the plane of the proper triangle abc is in the closed triangle and
// within d.
CDB_HD_CALL bool point_face_interior_within(const vec3f& p, const vec3f& a, const vec3f& b, const vec3f& c,
                                              float d) {
  return exact_sign(PointPlaneExcess{p, a, b, c, d}) <= 0 && exact_sign(InsideEdge{p, a, b, c}) >= 0 &&
         exact_sign(InsideEdge{p, b, c, a}) >= 0 && exact_sign(InsideEdge{p, c, a, b}) >= 0;
}

// The closest points of the two (non-parallel) lines lie on both closed segments and are
// within d.
CDB_HD_CALL bool segment_segment_interior_within(const vec3f& p0, const vec3f& p1, const vec3f& q0,
                                                   const vec3f& q1, float d) {
  if (exact_sign(EdgesCrossNorm{p0, p1, q0, q1}) == 0) return false;
  return exact_sign(LineLineExcess{p0, p1, q0, q1, d}) <= 0 && exact_sign(LineParameter{p0, p1, q0, q1, false}) >= 0 &&
         exact_sign(LineParameter{p0, p1, q0, q1, true}) >= 0 && exact_sign(LineParameter{q0, q1, p0, p1, false}) >= 0 &&
         exact_sign(LineParameter{q0, q1, p0, p1, true}) >= 0;
}

// Some axis separates the triangles' bounding boxes by more than d: then so are the
// triangles. Exact: lo - hi - d is a sum of three doubles (expansion.h).
CDB_HD_CALL bool boxes_apart_by_more_than(const vec3f* s, const vec3f* t, float d) {
  for (int axis = 0; axis < 3; ++axis) {
    float s_lo = coordinate(s[0], axis), s_hi = s_lo, t_lo = coordinate(t[0], axis), t_hi = t_lo;
    for (int k = 1; k < 3; ++k) {
      s_lo = min_of(s_lo, coordinate(s[k], axis));
      s_hi = max_of(s_hi, coordinate(s[k], axis));
      t_lo = min_of(t_lo, coordinate(t[k], axis));
      t_hi = max_of(t_hi, coordinate(t[k], axis));
    }
    const double gap_st[3] = {double(t_lo), -double(s_hi), -double(d)};
    const double gap_ts[3] = {double(s_lo), -double(t_hi), -double(d)};
    if (sign_of_exact_sum(gap_st, 3) > 0 || sign_of_exact_sum(gap_ts, 3) > 0) return true;
  }
  return false;
}

// Vertices of s against the proper triangle t (when it is one) and against t's edges.
CDB_HD_CALL bool vertices_within(const vec3f* s, const vec3f* t, bool t_proper, float d) {
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      if (point_segment_interior_within(s[i], t[j], t[(j + 1) % 3], d)) return true;
    if (t_proper && point_face_interior_within(s[i], t[0], t[1], t[2], d)) return true;
  }
  return false;
}

}  // namespace proximity

// Is the Euclidean distance between the closed triangles (a0, a1, a2) and (b0, b1, b2) at
// most d? Exact for float vertices (finite) and float d; d = 0 is the intersection test,
// d < 0 or NaN is never met, d = +inf always.
CDB_HD_CALL bool triangles_within(const vec3f& a0, const vec3f& a1, const vec3f& a2, const vec3f& b0,
                                    const vec3f& b1, const vec3f& b2, float d) {
  if (!(d >= 0)) return false;
  if (d > FLT_MAX) return true;
  const vec3f s[3] = {a0, a1, a2}, t[3] = {b0, b1, b2};
  if (proximity::boxes_apart_by_more_than(s, t, d)) return false;
  if (triangles_intersect(a0, a1, a2, b0, b1, b2)) return true;
  if (d == 0) return false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (proximity::point_point_within(s[i], t[j], d)) return true;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (proximity::segment_segment_interior_within(s[i], s[(i + 1) % 3], t[j], t[(j + 1) % 3], d)) return true;
  const bool s_proper = narrow::classify_triangle(a0, a1, a2).kind == narrow::TriangleShape::triangle;
  const bool t_proper = narrow::classify_triangle(b0, b1, b2).kind == narrow::TriangleShape::triangle;
  return proximity::vertices_within(s, t, t_proper, d) || proximity::vertices_within(t, s, s_proper, d);
}

}  // namespace cdb
