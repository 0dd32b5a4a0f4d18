#pragma once
// Exact intersection test of two closed triangles given by float vertices: touching at a
// vertex or along an edge counts, coplanar overlap counts, and degenerate triangles (all
// three vertices equal: a point; collinear: a segment) are tested as what they are.
//
// Every decision is a sign of orient3d / orient2d (predicates.h, exact) or a comparison of
// input coordinates, so the answer is the exact one for the float inputs.
//
// Proper (non-degenerate) pairs use Guigue and Devillers, "Fast and Robust Triangle-Triangle
// Overlap Test Using Orientation Predicates", JGT 8(1), 2003: reject when one triangle lies
// strictly on one side of the other's plane; otherwise permute each triangle so that its
// first vertex is alone on its side of the other's plane, and the triangles meet iff the
// two intervals cut on the planes' common line overlap, which is two orient3d signs. With
// exact predicates the paper's case analysis is exact, zeros included. The coplanar case
// projects both triangles to the coordinate plane of a nonzero component of the normal (an
// affine bijection of the common plane, so intersection is preserved) and tests in 2D:
// closed triangles meet iff an edge of one meets an edge of the other or a vertex of one
// lies in the other (if no boundaries meet, they are disjoint or one contains the other).
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"
#include "cdbench/narrow/predicates.h"

namespace cdb {
namespace narrow {

// --- 2D (after projection) ---------------------------------------------------------------

// q in the closed bounding box of segment [a, b]; for q on the line ab, q on the segment.
CDB_HD_INLINE bool in_segment_box(point2f a, point2f b, point2f q) {
  return min_of(a.x, b.x) <= q.x && q.x <= max_of(a.x, b.x) && min_of(a.y, b.y) <= q.y && q.y <= max_of(a.y, b.y);
}

// Closed segments [a, b] and [c, d]; either may be a single point.
CDB_HD_INLINE bool segments_meet_2d(point2f a, point2f b, point2f c, point2f d) {
  const int abc = orient2d(a, b, c), abd = orient2d(a, b, d);
  const int cda = orient2d(c, d, a), cdb = orient2d(c, d, b);
  if (abc * abd < 0 && cda * cdb < 0) return true;  // proper crossing
  // Otherwise they meet only where an endpoint lies on the other segment (collinear with it
  // and inside its box); for a one-point segment orient2d is 0 and the box is the point.
  return (abc == 0 && in_segment_box(a, b, c)) || (abd == 0 && in_segment_box(a, b, d)) ||
         (cda == 0 && in_segment_box(c, d, a)) || (cdb == 0 && in_segment_box(c, d, b));
}

// q in the closed triangle (a, b, c) of nonzero area, either orientation.
CDB_HD_INLINE bool point_in_triangle_2d(point2f q, point2f a, point2f b, point2f c) {
  const int s0 = orient2d(a, b, q), s1 = orient2d(b, c, q), s2 = orient2d(c, a, q);
  const bool negative = s0 < 0 || s1 < 0 || s2 < 0, positive = s0 > 0 || s1 > 0 || s2 > 0;
  return !(negative && positive);
}

// Closed segment [s0, s1] (possibly a point) and closed triangle (a, b, c) of nonzero area.
CDB_HD_INLINE bool segment_meets_triangle_2d(point2f s0, point2f s1, point2f a, point2f b, point2f c) {
  return point_in_triangle_2d(s0, a, b, c) || segments_meet_2d(s0, s1, a, b) || segments_meet_2d(s0, s1, b, c) ||
         segments_meet_2d(s0, s1, c, a);
}

// Two closed triangles of nonzero area.
CDB_HD_INLINE bool triangles_meet_2d(point2f p1, point2f q1, point2f r1, point2f p2, point2f q2, point2f r2) {
  const point2f t1[3] = {p1, q1, r1}, t2[3] = {p2, q2, r2};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (segments_meet_2d(t1[i], t1[(i + 1) % 3], t2[j], t2[(j + 1) % 3])) return true;
  return point_in_triangle_2d(p1, p2, q2, r2) || point_in_triangle_2d(p2, p1, q1, r1);
}

// --- shapes ------------------------------------------------------------------------------

// An axis whose coordinate plane the points a, b, c project to with nonzero area, i.e. a
// nonzero component of (b - a) x (c - a); -1 when the three are collinear (or equal).
CDB_HD_INLINE int plane_axis(const vec3f& a, const vec3f& b, const vec3f& c) {
  for (int axis = 2; axis >= 0; --axis)
    if (orient2d(drop_axis(a, axis), drop_axis(b, axis), drop_axis(c, axis)) != 0) return axis;
  return -1;
}

// What a triangle's three vertices span.
struct TriangleShape {
  enum Kind { point, segment, triangle } kind;
  int axis;        // triangle: see plane_axis
  vec3f s0, s1;    // segment: its end points (the extreme vertices); point: s0
};

CDB_HD_INLINE TriangleShape classify_triangle(const vec3f& a, const vec3f& b, const vec3f& c) {
  TriangleShape t{TriangleShape::triangle, plane_axis(a, b, c), a, a};
  if (t.axis >= 0) return t;
  // Collinear: along any axis on which the vertices differ, their order is their order on
  // the line, so the extreme two along it span the segment.
  for (int axis = 0; axis < 3; ++axis) {
    const float ka = coordinate(a, axis), kb = coordinate(b, axis), kc = coordinate(c, axis);
    if (ka == kb && kb == kc) continue;
    t.kind = TriangleShape::segment;
    t.s0 = ka <= kb && ka <= kc ? a : kb <= kc ? b : c;
    t.s1 = ka >= kb && ka >= kc ? a : kb >= kc ? b : c;
    return t;
  }
  t.kind = TriangleShape::point;
  return t;
}

// --- 3D, degenerate cases ----------------------------------------------------------------

CDB_HD_INLINE bool same_point(const vec3f& a, const vec3f& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// q on the closed segment [s0, s1] (s0 != s1).
CDB_HD_INLINE bool point_on_segment(const vec3f& q, const vec3f& s0, const vec3f& s1) {
  if (plane_axis(s0, s1, q) >= 0) return false;  // not collinear
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = min_of(coordinate(s0, axis), coordinate(s1, axis));
    const float hi = max_of(coordinate(s0, axis), coordinate(s1, axis));
    if (coordinate(q, axis) < lo || coordinate(q, axis) > hi) return false;
  }
  return true;
}

// q in the closed proper triangle (a, b, c) whose plane projects along `axis`.
CDB_HD_INLINE bool point_in_triangle(const vec3f& q, const vec3f& a, const vec3f& b, const vec3f& c, int axis) {
  return orient3d(a, b, c, q) == 0 &&
         point_in_triangle_2d(drop_axis(q, axis), drop_axis(a, axis), drop_axis(b, axis), drop_axis(c, axis));
}

// Closed segments [s0, s1] and [u0, u1] (neither a point).
CDB_HD_INLINE bool segments_meet(const vec3f& s0, const vec3f& s1, const vec3f& u0, const vec3f& u1) {
  if (orient3d(s0, s1, u0, u1) != 0) return false;  // not coplanar: skew or parallel apart
  // Coplanar: project along a nonzero normal component of the plane they span; if all four
  // are collinear, along an axis other than one on which s0 and s1 differ (the line then
  // projects one to one).
  int axis = plane_axis(s0, s1, u0);
  if (axis < 0) axis = plane_axis(s0, s1, u1);
  if (axis < 0) {
    const int along = s0.x != s1.x ? 0 : s0.y != s1.y ? 1 : 2;
    axis = (along + 1) % 3;
  }
  return segments_meet_2d(drop_axis(s0, axis), drop_axis(s1, axis), drop_axis(u0, axis), drop_axis(u1, axis));
}

// Closed segment [s0, s1] (not a point) and closed proper triangle (a, b, c).
CDB_HD_INLINE bool segment_meets_triangle(const vec3f& s0, const vec3f& s1, const vec3f& a, const vec3f& b,
                                          const vec3f& c, int axis) {
  const int o0 = orient3d(a, b, c, s0), o1 = orient3d(a, b, c, s1);
  if (o0 * o1 > 0) return false;  // strictly on one side
  if (o0 == 0 && o1 == 0)
    return segment_meets_triangle_2d(drop_axis(s0, axis), drop_axis(s1, axis), drop_axis(a, axis),
                                     drop_axis(b, axis), drop_axis(c, axis));
  // The segment's line crosses the plane at one point, which lies on the segment; it is in
  // the closed triangle iff the line passes no edge on the wrong side: the three signs of
  // orient3d(s0, s1, edge) are not of both strict signs.
  const int e0 = orient3d(s0, s1, a, b), e1 = orient3d(s0, s1, b, c), e2 = orient3d(s0, s1, c, a);
  const bool negative = e0 < 0 || e1 < 0 || e2 < 0, positive = e0 > 0 || e1 > 0 || e2 > 0;
  return !(negative && positive);
}

// --- 3D, proper triangles (Guigue-Devillers) ---------------------------------------------

// Both triangles proper, p1 alone on its side of plane 2 and p2 alone on its side of plane
// 1, oriented as the paper's canonical form: the intervals overlap iff neither orient3d
// below is positive.
CDB_HD_INLINE bool gd_intervals_overlap(const vec3f& p1, const vec3f& q1, const vec3f& r1, const vec3f& p2,
                                        const vec3f& q2, const vec3f& r2) {
  return orient3d(q1, p2, p1, q2) <= 0 && orient3d(p1, p2, r1, r2) <= 0;
}

CDB_HD_INLINE bool coplanar_triangles_meet(const vec3f& p1, const vec3f& q1, const vec3f& r1, int axis,
                                           const vec3f& p2, const vec3f& q2, const vec3f& r2) {
  return triangles_meet_2d(drop_axis(p1, axis), drop_axis(q1, axis), drop_axis(r1, axis), drop_axis(p2, axis),
                           drop_axis(q2, axis), drop_axis(r2, axis));
}

// Permutes triangle 2 (signs dp2, dq2, dr2 against plane 1) into canonical form; triangle 1
// already is. All-zero signs mean coplanar.
CDB_HD_INLINE bool gd_canonical_t2(const vec3f& p1, const vec3f& q1, const vec3f& r1, int axis1, const vec3f& p2,
                                   const vec3f& q2, const vec3f& r2, int dp2, int dq2, int dr2) {
  if (dp2 > 0) {
    if (dq2 > 0) return gd_intervals_overlap(p1, r1, q1, r2, p2, q2);
    if (dr2 > 0) return gd_intervals_overlap(p1, r1, q1, q2, r2, p2);
    return gd_intervals_overlap(p1, q1, r1, p2, q2, r2);
  }
  if (dp2 < 0) {
    if (dq2 < 0) return gd_intervals_overlap(p1, q1, r1, r2, p2, q2);
    if (dr2 < 0) return gd_intervals_overlap(p1, q1, r1, q2, r2, p2);
    return gd_intervals_overlap(p1, r1, q1, p2, q2, r2);
  }
  if (dq2 < 0) {
    if (dr2 >= 0) return gd_intervals_overlap(p1, r1, q1, q2, r2, p2);
    return gd_intervals_overlap(p1, q1, r1, p2, q2, r2);
  }
  if (dq2 > 0) {
    if (dr2 > 0) return gd_intervals_overlap(p1, r1, q1, p2, q2, r2);
    return gd_intervals_overlap(p1, q1, r1, q2, r2, p2);
  }
  if (dr2 > 0) return gd_intervals_overlap(p1, q1, r1, r2, p2, q2);
  if (dr2 < 0) return gd_intervals_overlap(p1, r1, q1, r2, p2, q2);
  return coplanar_triangles_meet(p1, q1, r1, axis1, p2, q2, r2);
}

// Two proper triangles; axis1: plane_axis of triangle 1.
CDB_HD_INLINE bool proper_triangles_meet(const vec3f& p1, const vec3f& q1, const vec3f& r1, int axis1,
                                         const vec3f& p2, const vec3f& q2, const vec3f& r2) {
  const int dp1 = orient3d(p2, q2, r2, p1), dq1 = orient3d(p2, q2, r2, q1), dr1 = orient3d(p2, q2, r2, r1);
  if (dp1 * dq1 > 0 && dp1 * dr1 > 0) return false;
  const int dp2 = orient3d(p1, q1, r1, p2), dq2 = orient3d(p1, q1, r1, q2), dr2 = orient3d(p1, q1, r1, r2);
  if (dp2 * dq2 > 0 && dp2 * dr2 > 0) return false;
  // Permute triangle 1 into canonical form (p1 alone on its side of plane 2), flipping
  // triangle 2's orientation where that flips the side.
  if (dp1 > 0) {
    if (dq1 > 0) return gd_canonical_t2(r1, p1, q1, axis1, p2, r2, q2, dp2, dr2, dq2);
    if (dr1 > 0) return gd_canonical_t2(q1, r1, p1, axis1, p2, r2, q2, dp2, dr2, dq2);
    return gd_canonical_t2(p1, q1, r1, axis1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dp1 < 0) {
    if (dq1 < 0) return gd_canonical_t2(r1, p1, q1, axis1, p2, q2, r2, dp2, dq2, dr2);
    if (dr1 < 0) return gd_canonical_t2(q1, r1, p1, axis1, p2, q2, r2, dp2, dq2, dr2);
    return gd_canonical_t2(p1, q1, r1, axis1, p2, r2, q2, dp2, dr2, dq2);
  }
  if (dq1 < 0) {
    if (dr1 >= 0) return gd_canonical_t2(q1, r1, p1, axis1, p2, r2, q2, dp2, dr2, dq2);
    return gd_canonical_t2(p1, q1, r1, axis1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dq1 > 0) {
    if (dr1 > 0) return gd_canonical_t2(p1, q1, r1, axis1, p2, r2, q2, dp2, dr2, dq2);
    return gd_canonical_t2(q1, r1, p1, axis1, p2, q2, r2, dp2, dq2, dr2);
  }
  if (dr1 > 0) return gd_canonical_t2(r1, p1, q1, axis1, p2, q2, r2, dp2, dq2, dr2);
  if (dr1 < 0) return gd_canonical_t2(r1, p1, q1, axis1, p2, r2, q2, dp2, dr2, dq2);
  return coplanar_triangles_meet(p1, q1, r1, axis1, p2, q2, r2);
}

// A (possibly degenerate) shape against a proper triangle.
CDB_HD_INLINE bool shape_meets_proper(const TriangleShape& s, const vec3f& a, const vec3f& b, const vec3f& c,
                                      int axis) {
  if (s.kind == TriangleShape::point) return point_in_triangle(s.s0, a, b, c, axis);
  return segment_meets_triangle(s.s0, s.s1, a, b, c, axis);
}

}  // namespace narrow

// Do the closed triangles (p1, q1, r1) and (p2, q2, r2) share a point? Exact for float input.
// Out of line in device code: its inlined predicates are large, and every kernel calling it
// (the intersection and the proximity test) would carry a copy.
CDB_HD_CALL bool triangles_intersect(const vec3f& p1, const vec3f& q1, const vec3f& r1, const vec3f& p2,
                                       const vec3f& q2, const vec3f& r2) {
  using narrow::TriangleShape;
  const TriangleShape t1 = narrow::classify_triangle(p1, q1, r1);
  const TriangleShape t2 = narrow::classify_triangle(p2, q2, r2);
  if (t1.kind == TriangleShape::triangle && t2.kind == TriangleShape::triangle)
    return narrow::proper_triangles_meet(p1, q1, r1, t1.axis, p2, q2, r2);
  if (t2.kind == TriangleShape::triangle) return narrow::shape_meets_proper(t1, p2, q2, r2, t2.axis);
  if (t1.kind == TriangleShape::triangle) return narrow::shape_meets_proper(t2, p1, q1, r1, t1.axis);
  // Both degenerate: points and segments.
  if (t1.kind == TriangleShape::point && t2.kind == TriangleShape::point) return narrow::same_point(t1.s0, t2.s0);
  if (t1.kind == TriangleShape::point) return narrow::point_on_segment(t1.s0, t2.s0, t2.s1);
  if (t2.kind == TriangleShape::point) return narrow::point_on_segment(t2.s0, t1.s0, t1.s1);
  return narrow::segments_meet(t1.s0, t1.s1, t2.s0, t2.s1);
}

}  // namespace cdb
