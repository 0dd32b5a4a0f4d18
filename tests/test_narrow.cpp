// Narrow phase: exact orientation predicates and the closed triangle-triangle test, against
// hand cases with known answers and against an independent exact separating-axis oracle in
// integer arithmetic.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "cdbench/narrow/contacts.h"
#include "cdbench/narrow/predicates.h"
#include "cdbench/narrow/triangle_intersect.h"
#include "narrow_cases.h"
#include "param_name.h"

namespace cdb {
namespace {

bool float_intersect(const ITri& P, const ITri& Q, const Placement& p) {
  return triangles_intersect(place(P[0], p), place(P[1], p), place(P[2], p), place(Q[0], p), place(Q[1], p),
                             place(Q[2], p));
}

// --- predicates ----------------------------------------------------------------------------

vec3f v3(float x, float y, float z) { return {x, y, z}; }
point2f p2(float x, float y) { return {x, y}; }

TEST(Predicates, Orient3dSignConvention) {
  const vec3f o = v3(0, 0, 0), x = v3(1, 0, 0), y = v3(0, 1, 0);
  EXPECT_EQ(orient3d(o, x, y, v3(0, 0, 1)), 1);  // on the side of (x - o) x (y - o)
  EXPECT_EQ(orient3d(o, x, y, v3(0, 0, -1)), -1);
  EXPECT_EQ(orient3d(o, x, y, v3(5, -7, 0)), 0);
  EXPECT_EQ(orient3d(o, y, x, v3(0, 0, 1)), -1);
  EXPECT_EQ(orient3d_exact(o, x, y, v3(0, 0, 1)), 1);
  EXPECT_EQ(orient3d_exact(o, x, y, v3(5, -7, 0)), 0);
  EXPECT_EQ(orient2d(p2(0, 0), p2(1, 0), p2(0, 1)), 1);
  EXPECT_EQ(orient2d(p2(0, 0), p2(0, 1), p2(1, 0)), -1);
  EXPECT_EQ(orient2d(p2(0, 0), p2(1, 1), p2(3, 3)), 0);
}

// Coordinates whose differences are not doubles: a naive double evaluation returns 0 here,
// the exact sign is known in closed form.
TEST(Predicates, DifferencesThatAreNotDoubles) {
  // a = (s, 0), b = (L, L), c = (2L, 2L): (b - a) x (c - a) = (L - s) 2L - L (2L - s) = -sL.
  const float s = 1e-30f, L = 1e30f;
  const point2f a = p2(s, 0), b = p2(L, L), c = p2(2 * L, 2 * L);
  const double naive = (double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x);
  EXPECT_EQ(naive, 0.0);  // the case the filter must hand to the exact evaluation
  EXPECT_EQ(orient2d(a, b, c), -1);
  EXPECT_EQ(orient2d_exact(a, b, c), -1);
  EXPECT_EQ(orient2d(b, a, c), 1);
  // Lifted: d = (0, 0, L) above, det[b - a; c - a; d - a] = L * (-sL) < 0.
  const vec3f A = v3(s, 0, 0), B = v3(L, L, 0), C = v3(2 * L, 2 * L, 0), D = v3(0, 0, L);
  EXPECT_EQ(orient3d(A, B, C, D), -1);
  EXPECT_EQ(orient3d_exact(A, B, C, D), -1);
  EXPECT_EQ(orient3d(A, C, B, D), 1);
  // And the same at the bottom of the float range: s a subnormal, L = 1.
  EXPECT_EQ(orient3d(v3(1e-45f, 0, 0), v3(1, 1, 0), v3(2, 2, 0), v3(0, 0, 1)), -1);
}

// Filtered and exact evaluations against __int128 determinants of integer points scaled by
// a power of two, many of them exactly or nearly coplanar.
TEST(Predicates, MatchExactIntegerDeterminants) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int64_t> coord(-(1 << 19), 1 << 19), edge(-(1 << 20), 1 << 20), small(-2, 2);
  auto det_sign = [](const IVec& a, const IVec& b, const IVec& c, const IVec& d) {
    const IVec u = b - a, v = c - a, w = d - a;
    const __int128 det = __int128(u.x) * (__int128(v.y) * w.z - __int128(v.z) * w.y) -
                         __int128(u.y) * (__int128(v.x) * w.z - __int128(v.z) * w.x) +
                         __int128(u.z) * (__int128(v.x) * w.y - __int128(v.y) * w.x);
    return det > 0 ? 1 : det < 0 ? -1 : 0;
  };
  auto plus = [](IVec a, IVec b, int64_t k) { return IVec{a.x + k * b.x, a.y + k * b.y, a.z + k * b.z}; };
  int zeros = 0, checked = 0;
  for (int it = 0; it < 30000; ++it) {
    // Coordinates below 2^23: exact in float, differences exact in double, products of
    // three past 2^53, so the double evaluation rounds.
    const IVec a{coord(rng), coord(rng), coord(rng)}, U{edge(rng), edge(rng), edge(rng)};
    const IVec V{edge(rng), edge(rng), edge(rng)};
    const IVec s1{small(rng), small(rng), small(rng)}, s2{small(rng), small(rng), small(rng)};
    IVec b = plus(a, U, 1), c, d;
    if (it % 3 == 0) {  // d exactly in the plane of a, b, c
      c = plus(a, V, 1);
      d = plus(plus(a, U, small(rng)), V, small(rng));
    } else if (it % 3 == 1) {  // d nudged off that plane
      c = plus(a, V, 1);
      d = plus(plus(plus(a, U, small(rng)), V, small(rng)), s1, 1);
    } else {  // a thin configuration: all four near the line through a along U
      c = plus(plus(a, U, 2), s1, 1);
      d = plus(plus(a, U, -1), s2, 1);
    }
    const int expected = det_sign(a, b, c, d);
    zeros += expected == 0;
    for (const Placement& p : {Placement{0, 0, ""}, Placement{0, 100, ""}, Placement{0, -126, ""}}) {
      const vec3f A = place(a, p), B = place(b, p), C = place(c, p), D = place(d, p);
      ASSERT_EQ(orient3d(A, B, C, D), expected) << "iteration " << it << " exponent " << p.exponent;
      ASSERT_EQ(orient3d_exact(A, B, C, D), expected);
      const int expected2d = det_sign({a.x, a.y, 0}, {b.x, b.y, 0}, {c.x, c.y, 0}, {0, 0, 1});
      ASSERT_EQ(orient2d(drop_axis(A, 2), drop_axis(B, 2), drop_axis(C, 2)), expected2d);
      ++checked;
    }
  }
  EXPECT_GT(zeros, 9000);  // every one of them needed the exact evaluation
  EXPECT_EQ(checked, 90000);
}

// --- triangle-triangle: hand cases -----------------------------------------------------------

struct HandCase {
  const char* name;
  ITri P, Q;
  bool meet;
};

// T: the right triangle (0,0,0), (4,0,0), (0,4,0) in the plane z = 0.
const ITri T = {IVec{0, 0, 0}, IVec{4, 0, 0}, IVec{0, 4, 0}};

std::vector<HandCase> hand_cases() {
  return {
      {"coplanar overlapping", T, {IVec{1, 1, 0}, IVec{5, 1, 0}, IVec{1, 5, 0}}, true},
      {"coplanar disjoint", T, {IVec{3, 3, 0}, IVec{6, 3, 0}, IVec{3, 6, 0}}, false},
      {"coplanar, one contains the other", T, {IVec{1, 1, 0}, IVec{2, 1, 0}, IVec{1, 2, 0}}, true},
      {"coplanar, shared vertex only", T, {IVec{4, 0, 0}, IVec{6, 0, 0}, IVec{5, 2, 0}}, true},
      {"coplanar, shared edge", T, {IVec{0, 4, 0}, IVec{4, 0, 0}, IVec{4, 4, 0}}, true},
      {"coplanar, vertex on edge", T, {IVec{2, 2, 0}, IVec{5, 3, 0}, IVec{3, 5, 0}}, true},
      {"coplanar, edges crossing", T, {IVec{-1, 1, 0}, IVec{5, 1, 0}, IVec{2, -3, 0}}, true},
      {"vertex on face", T, {IVec{1, 1, 0}, IVec{1, 1, 5}, IVec{2, 3, 5}}, true},
      {"vertex above face", T, {IVec{1, 1, 1}, IVec{1, 1, 5}, IVec{2, 3, 5}}, false},
      {"piercing", T, {IVec{1, 1, -2}, IVec{1, 1, 3}, IVec{-3, -3, 0}}, true},
      {"edge-edge crossing", T, {IVec{2, 0, -1}, IVec{2, 0, 1}, IVec{2, -3, 0}}, true},
      {"edge-edge, apart", T, {IVec{2, -1, -1}, IVec{2, -1, 1}, IVec{2, -3, 0}}, false},
      {"edge on edge, planes at an angle", T, {IVec{1, 0, 0}, IVec{3, 0, 0}, IVec{2, -2, 3}}, true},
      {"parallel planes", T, {IVec{0, 0, 1}, IVec{4, 0, 1}, IVec{0, 4, 1}}, false},
      {"identical", T, T, true},
      {"point on face", T, {IVec{1, 1, 0}, IVec{1, 1, 0}, IVec{1, 1, 0}}, true},
      {"point at a vertex", T, {IVec{4, 0, 0}, IVec{4, 0, 0}, IVec{4, 0, 0}}, true},
      {"point on an edge", T, {IVec{2, 2, 0}, IVec{2, 2, 0}, IVec{2, 2, 0}}, true},
      {"point off the face, in its plane", T, {IVec{3, 3, 0}, IVec{3, 3, 0}, IVec{3, 3, 0}}, false},
      {"point above the face", T, {IVec{1, 1, 1}, IVec{1, 1, 1}, IVec{1, 1, 1}}, false},
      {"segment piercing", T, {IVec{1, 1, -1}, IVec{1, 1, 1}, IVec{1, 1, 0}}, true},
      {"segment touching with its end", T, {IVec{1, 1, 0}, IVec{1, 1, 1}, IVec{1, 1, 2}}, true},
      {"segment ending above", T, {IVec{1, 1, 1}, IVec{1, 1, 2}, IVec{1, 1, 3}}, false},
      {"segment in the plane, crossing", T, {IVec{-1, 1, 0}, IVec{5, 1, 0}, IVec{2, 1, 0}}, true},
      {"segment in the plane, outside", T, {IVec{-1, 5, 0}, IVec{5, 5, 0}, IVec{2, 5, 0}}, false},
      {"segment through an edge, off plane", T, {IVec{2, -1, 1}, IVec{2, 1, -1}, IVec{2, 0, 0}}, true},
      {"segment passing beside an edge", T, {IVec{3, 2, 1}, IVec{3, 2, -1}, IVec{3, 2, 0}}, false},
      {"segments collinear, overlapping", {IVec{0, 0, 0}, IVec{2, 0, 0}, IVec{1, 0, 0}},
       {IVec{1, 0, 0}, IVec{3, 0, 0}, IVec{2, 0, 0}}, true},
      {"segments collinear, end to end", {IVec{0, 0, 0}, IVec{2, 0, 0}, IVec{1, 0, 0}},
       {IVec{2, 0, 0}, IVec{4, 0, 0}, IVec{3, 0, 0}}, true},
      {"segments collinear, apart", {IVec{0, 0, 0}, IVec{2, 0, 0}, IVec{1, 0, 0}},
       {IVec{3, 0, 0}, IVec{5, 0, 0}, IVec{4, 0, 0}}, false},
      {"segments crossing", {IVec{0, 0, 0}, IVec{2, 2, 2}, IVec{1, 1, 1}}, {IVec{0, 2, 0}, IVec{2, 0, 2}, IVec{1, 1, 1}},
       true},
      {"segments skew", {IVec{0, 0, 0}, IVec{2, 2, 0}, IVec{1, 1, 0}}, {IVec{0, 2, 1}, IVec{2, 0, 1}, IVec{1, 1, 1}},
       false},
      {"segments parallel", {IVec{0, 0, 0}, IVec{2, 2, 0}, IVec{1, 1, 0}}, {IVec{1, 0, 0}, IVec{3, 2, 0}, IVec{2, 1, 0}},
       false},
      {"segment and point on it", {IVec{0, 0, 0}, IVec{2, 4, 6}, IVec{1, 2, 3}}, {IVec{1, 2, 3}, IVec{1, 2, 3}, IVec{1, 2, 3}},
       true},
      {"segment and point beside it", {IVec{0, 0, 0}, IVec{2, 4, 6}, IVec{1, 2, 3}},
       {IVec{1, 2, 4}, IVec{1, 2, 4}, IVec{1, 2, 4}}, false},
      {"segment and point on its line, past the end", {IVec{0, 0, 0}, IVec{2, 4, 6}, IVec{1, 2, 3}},
       {IVec{3, 6, 9}, IVec{3, 6, 9}, IVec{3, 6, 9}}, false},
      {"same point", {IVec{1, 2, 3}, IVec{1, 2, 3}, IVec{1, 2, 3}}, {IVec{1, 2, 3}, IVec{1, 2, 3}, IVec{1, 2, 3}}, true},
      {"different points", {IVec{1, 2, 3}, IVec{1, 2, 3}, IVec{1, 2, 3}}, {IVec{1, 2, 4}, IVec{1, 2, 4}, IVec{1, 2, 4}},
       false},
      {"identical segments", {IVec{0, 0, 0}, IVec{2, 2, 0}, IVec{1, 1, 0}}, {IVec{0, 0, 0}, IVec{2, 2, 0}, IVec{1, 1, 0}},
       true},
  };
}

class NarrowHand : public testing::TestWithParam<HandCase> {};

TEST_P(NarrowHand, KnownAnswerEverywhere) {
  const HandCase& c = GetParam();
  ASSERT_EQ(sat_oracle_intersect(c.P, c.Q), c.meet) << "the oracle disagrees with the hand answer";
  for (const Placement& p : kPlacements) {
    EXPECT_EQ(float_intersect(c.P, c.Q, p), c.meet) << p.name;
    EXPECT_EQ(float_intersect(c.Q, c.P, p), c.meet) << p.name << ", swapped";
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, NarrowHand, testing::ValuesIn(hand_cases()),
                         [](const testing::TestParamInfo<HandCase>& info) {
                           return param_name(info.param.name);
                         });

// One float ulp decides: touching at exactly representable points, apart by the smallest step.
TEST(NarrowFloat, OneUlpDecides) {
  const vec3f a = v3(0, 0, 0), b = v3(4, 0, 0), c = v3(0, 4, 0);
  const float just_above_2 = std::nextafter(2.0f, 3.0f);
  // A vertex on the hypotenuse x + y = 4, then one ulp past it.
  EXPECT_TRUE(triangles_intersect(a, b, c, v3(2, 2, 0), v3(5, 3, 0), v3(3, 5, 0)));
  EXPECT_FALSE(triangles_intersect(a, b, c, v3(2, just_above_2, 0), v3(5, 3, 0), v3(3, 5, 0)));
  // A vertex touching the face from above, then one subnormal above it.
  EXPECT_TRUE(triangles_intersect(a, b, c, v3(1, 1, 0), v3(1, 1, 5), v3(2, 3, 5)));
  EXPECT_FALSE(triangles_intersect(a, b, c, v3(1, 1, 1e-45f), v3(1, 1, 5), v3(2, 3, 5)));
  EXPECT_TRUE(triangles_intersect(a, b, c, v3(1, 1, -1e-45f), v3(1, 1, 5), v3(2, 3, 5)));
}

TEST(NarrowFloat, LiteralHugeAndTinyScales) {
  for (const float L : {1e30f, 1e-30f, 3e38f}) {
    const float h = L / 2;  // exact: a power-of-two scaling
    const vec3f a = v3(0, 0, 0), b = v3(L, 0, 0), c = v3(0, L, 0);
    // A triangle standing on the hypotenuse with one vertex, then nudged one ulp outward.
    EXPECT_TRUE(triangles_intersect(a, b, c, v3(h, h, 0), v3(L, L, L), v3(L, L, -L))) << L;
    EXPECT_FALSE(triangles_intersect(a, b, c, v3(std::nextafter(h, L), h, 0), v3(L, L, L), v3(L, L, -L))) << L;
    // Coplanar, overlapping by one ulp and separated by one ulp.
    EXPECT_TRUE(triangles_intersect(a, b, c, v3(std::nextafter(h, 0.0f), h, 0), v3(L, h, 0), v3(h, L, 0))) << L;
    EXPECT_FALSE(triangles_intersect(a, b, c, v3(std::nextafter(h, L), h, 0), v3(L, h, 0), v3(h, L, 0))) << L;
  }
}

// A 1e-3 triangle in the plane x = 1e6 and a thin triangle whose edge pierces that plane at
// a chosen (y, z); its third vertex lies beyond the plane in the direction (dy, dz), so it
// cuts the plane along a segment from (y, z) pointing that way: inside the small triangle,
// through its vertex and edge, and just outside its hypotenuse y + z = 1e-3 and its edge z = 0.
TEST(NarrowFloat, MillionOffsetWithThousandthFeatures) {
  const float X = 1e6f, step = 0.0625f;  // the float spacing at 1e6
  const vec3f a = v3(X, 0, 0), b = v3(X, 1e-3f, 0), c = v3(X, 0, 1e-3f);
  auto piercing = [&](float y, float z, float dy, float dz) {
    return triangles_intersect(a, b, c, v3(X - step, y, z), v3(X + step, y, z), v3(X + step, y + dy, z + dz));
  };
  EXPECT_TRUE(piercing(2e-4f, 3e-4f, 1e-3f, 1e-3f));
  EXPECT_TRUE(piercing(0, 0, -1e-3f, -1e-3f));         // through the vertex a
  EXPECT_TRUE(piercing(5e-4f, 0, 0, -1e-3f));          // through the edge ab
  EXPECT_FALSE(piercing(5e-4f, -1e-10f, 0, -1e-3f));   // just below it
  EXPECT_FALSE(piercing(2e-4f, 8.1e-4f, 1e-3f, 1e-3f));  // past the hypotenuse
  EXPECT_TRUE(piercing(2e-4f, 8.1e-4f, -1e-3f, -1e-3f));  // past it, cutting back inside
}

// --- triangle-triangle: randomized against the oracle -----------------------------------------

struct RandomOutcome {
  int meet = 0, apart = 0;
};

RandomOutcome compare_with_oracle(uint64_t seed, int range, int count) {
  RandomPairs gen(seed, range);
  RandomOutcome out;
  for (int it = 0; it < count; ++it) {
    ITri P, Q;
    gen.next(P, Q);
    const bool expected = sat_oracle_intersect(P, Q);
    (expected ? out.meet : out.apart)++;
    const Placement& p = kPlacements[it % std::size(kPlacements)];
    // Symmetries that cannot change the answer: order of triangles, rotation and reversal
    // of vertex order, a permutation and reflection of the axes.
    const ITri P_rot = {P[1], P[2], P[0]}, Q_rev = {Q[2], Q[1], Q[0]};
    auto mirror = [](const ITri& t) {
      ITri m;
      for (int i = 0; i < 3; ++i) m[i] = {t[i].z, -t[i].x, t[i].y};
      return m;
    };
    const bool got[] = {float_intersect(P, Q, kPlacements[0]), float_intersect(P, Q, p), float_intersect(Q, P, p),
                        float_intersect(P_rot, Q_rev, p), float_intersect(mirror(P), mirror(Q), p)};
    for (size_t k = 0; k < std::size(got); ++k)
      if (got[k] != expected) {
        ADD_FAILURE() << "seed " << seed << " iteration " << it << " variant " << k << " at " << p.name
                      << ": expected " << expected << "; P = (" << P[0].x << "," << P[0].y << "," << P[0].z
                      << ") (" << P[1].x << "," << P[1].y << "," << P[1].z << ") (" << P[2].x << "," << P[2].y
                      << "," << P[2].z << "), Q = (" << Q[0].x << "," << Q[0].y << "," << Q[0].z << ") ("
                      << Q[1].x << "," << Q[1].y << "," << Q[1].z << ") (" << Q[2].x << "," << Q[2].y << ","
                      << Q[2].z << ")";
        return out;
      }
  }
  return out;
}

TEST(NarrowRandom, TinyLatticeAgreesWithOracle) {
  const RandomOutcome o = compare_with_oracle(1, 1, 60000);  // coordinates in {-1, 0, 1}
  EXPECT_GT(o.meet, 10000);
  EXPECT_GT(o.apart, 5000);
}

TEST(NarrowRandom, SmallLatticeAgreesWithOracle) {
  const RandomOutcome o = compare_with_oracle(2, 3, 60000);
  EXPECT_GT(o.meet, 10000);
  EXPECT_GT(o.apart, 10000);
}

TEST(NarrowRandom, WiderLatticeAgreesWithOracle) {
  const RandomOutcome o = compare_with_oracle(3, 40, 40000);
  EXPECT_GT(o.meet, 4000);
  EXPECT_GT(o.apart, 10000);
}

// --- true contacts over a pair list ------------------------------------------------------------

TEST(Contacts, CountsTrueContactsOfAPairList) {
  // A flat 3 x 3 vertex grid (8 triangles, all in z = 0) and one triangle floating above it.
  std::vector<vec3f> v;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) v.push_back(v3(float(i), float(j), 0));
  v.push_back(v3(0.5f, 0.5f, 1));
  v.push_back(v3(1.5f, 0.5f, 1));
  v.push_back(v3(0.5f, 1.5f, 1));
  std::vector<Tri> faces;
  for (uint32_t j = 0; j < 2; ++j)
    for (uint32_t i = 0; i < 2; ++i) {
      const uint32_t k = j * 3 + i;
      faces.push_back({k, k + 1, k + 4});
      faces.push_back({k, k + 4, k + 3});
    }
  faces.push_back({9, 10, 11});
  const std::vector<PrimPair> pairs = {
      {0, 1},  // share an edge
      {0, 2},  // share the vertex (1, 0)
      {0, 7},  // opposite corners of the grid: share the centre vertex
      {1, 6},  // (0,0)-(1,1)-(0,1) and (1,1)-(2,2)-(1,2): share the centre vertex
      {0, 8},  // the floating triangle
      {2, 5},  // (1,0)-(2,0)-(2,1) and (0,1)-(1,2)-(0,2): apart
  };
  EXPECT_EQ(count_true_contacts(faces, v, pairs), 4u);
  EXPECT_EQ(count_true_contacts(faces, v, {}), 0u);
  EXPECT_DOUBLE_EQ(contact_precision(4, 6), 4.0 / 6.0);
  EXPECT_DOUBLE_EQ(contact_precision(0, 0), 1.0);
}

}  // namespace
}  // namespace cdb
