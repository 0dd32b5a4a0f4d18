// Proximity of closed triangles (narrow/proximity.h): the exact decision "distance <= d"
// against an independent exact oracle in integer arithmetic (proximity_cases.h), hand cases
// with one-ulp decisions at large and small scales, the exact integers and the filter bound
// on their own, and the contact counts built on them (narrow/contacts.h).
#include <gtest/gtest.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/narrow/contacts.h"
#include "cdbench/narrow/proximity.h"
#include "proximity_cases.h"
#include "param_name.h"

namespace cdb {
namespace {

vec3f v3(float x, float y, float z) { return {x, y, z}; }

bool within(const ITri& P, const ITri& Q, float d, const Placement& p) {
  return triangles_within(place(P[0], p), place(P[1], p), place(P[2], p), place(Q[0], p), place(Q[1], p),
                          place(Q[2], p), d);
}

std::string describe(const ITri& P, const ITri& Q, int64_t quarters) {
  std::ostringstream s;
  for (const ITri* t : {&P, &Q}) {
    s << (t == &P ? "P =" : ", Q =");
    for (const IVec& v : *t) s << " (" << v.x << "," << v.y << "," << v.z << ")";
  }
  s << ", d = " << quarters << "/4";
  return s.str();
}

// --- the parts -------------------------------------------------------------------------------

// WideInt against __int128 on values that fit, and of_float on the extremes of float.
TEST(WideInt, ArithmeticMatchesInt128) {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<int64_t> small(-(int64_t(1) << 40), int64_t(1) << 40);
  auto value = [](const WideInt& w) {
    __int128 v = 0;
    for (int i = w.size - 1; i >= 0; --i) v = (v << 32) | w.limb[i];
    return w.sign < 0 ? -v : v;
  };
  auto exact = [](int64_t x) {  // x * 2^-149 as a float is exact for |x| < 2^24: use x < 2^24
    return WideInt::of_float(std::ldexp(float(x), -149));
  };
  for (int it = 0; it < 20000; ++it) {
    const int64_t a = small(rng) >> 17, b = small(rng) >> 17, c = small(rng) >> 17;  // below 2^24
    const WideInt A = exact(a), B = exact(b), C = exact(c);
    ASSERT_EQ(value(A), a);
    ASSERT_EQ(value(A + B), __int128(a) + b);
    ASSERT_EQ(value(A - B), __int128(a) - b);
    ASSERT_EQ(value(A * B * C - C * A), __int128(a) * b * c - __int128(c) * a);
    ASSERT_EQ((A - A).sign, 0);
  }
  const WideInt one = WideInt::of_float(1.0f);
  EXPECT_EQ(one.size, 5);  // 2^149: bit 149 is bit 21 of limb 4
  EXPECT_EQ(one.limb[4], 1u << 21);
  const WideInt tiny = WideInt::of_float(-1e-45f);  // -2^-149: -1 unit
  EXPECT_EQ(tiny.sign, -1);
  EXPECT_EQ(value(tiny), -1);
  const WideInt big = WideInt::of_float(FLT_MAX);  // (2^24 - 1) 2^104 units 2^-149: 2^277 - 2^253
  EXPECT_EQ(big.size, 9);
  EXPECT_EQ(big.limb[8], (1u << 21) - 1);
  EXPECT_EQ(big.limb[7], 0xE0000000u);
  EXPECT_EQ(WideInt::of_float(0.0f).sign, 0);
  EXPECT_EQ(WideInt::of_float(-0.0f).sign, 0);
}

// The filter bound holds where the double evaluation is far from exact: products of
// full-width mantissas, at the top and bottom of the float range.
TEST(BoundedDouble, BoundCoversTheRoundingError) {
  std::mt19937_64 rng(12);
  std::uniform_int_distribution<int32_t> mantissa(1 << 23, (1 << 24) - 1);
  int decided = 0;
  for (int it = 0; it < 20000; ++it) {
    const int exponent = it % 3 == 0 ? 100 : it % 3 == 1 ? -140 : -20;
    float c[6];
    for (float& x : c) x = std::ldexp(float(mantissa(rng)) * (rng() & 1 ? 1 : -1), exponent - 23);
    // ((c0 - c1)(c2 - c3) - (c4 - c5))^2-like tree of degree 4 and its exact value.
    const auto expr = [&](auto of_difference) {
      const auto x = of_difference(c[0], c[1]), y = of_difference(c[2], c[3]), z = of_difference(c[4], c[5]);
      const auto w = x * y - z * x;
      return w * w - y * y * z * z;
    };
    const BoundedDouble a = expr([](float p, float q) { return BoundedDouble::of_difference(p, q); });
    const WideInt e = expr([](float p, float q) { return WideInt::of_difference(p, q); });
    if (a.value > a.bound()) {
      ASSERT_EQ(e.sign, 1) << it;
      ++decided;
    } else if (a.value < -a.bound()) {
      ASSERT_EQ(e.sign, -1) << it;
      ++decided;
    }
  }
  EXPECT_GT(decided, 19000);
}

// --- randomized against the oracle ----------------------------------------------------------

struct Outcome {
  int within = 0, apart = 0, ties = 0;
};

// Random pairs on a lattice with d drawn near their true distance; each pair also swapped,
// rotated in vertex order, mirrored, and, when `similar`, mapped by the integer similarity
// (full-width mantissas, d scaled alike), at one of the placements of narrow_cases.h.
Outcome compare_with_oracle(uint64_t seed, int range, int count, bool similar) {
  RandomPairs gen(seed, range);
  std::mt19937_64 rng(seed * 7919);
  Outcome out;
  for (int it = 0; it < count; ++it) {
    ITri P, Q;
    gen.next(P, Q);
    const int64_t quarters = quarters_near_decision(P, Q, range, rng);
    const ProximityVerdict v = oracle_within(P, Q, quarters);
    (v.within ? out.within : out.apart)++;
    out.ties += v.tie;
    const Placement& p = kPlacements[it % std::size(kPlacements)];
    ITri A = P, B = Q;
    int64_t scaled = quarters;
    if (similar) {
      A = similarity(P), B = similarity(Q);
      scaled = quarters * kSimilarityScale;
    }
    const float d = place_distance(scaled, p);
    const ITri A_rot = {A[1], A[2], A[0]}, B_rev = {B[2], B[1], B[0]};
    auto mirror = [](const ITri& t) {
      ITri m;
      for (int i = 0; i < 3; ++i) m[i] = {t[i].z, -t[i].x, t[i].y};
      return m;
    };
    const bool got[] = {within(A, B, d, p), within(B, A, d, p), within(A_rot, B_rev, d, p),
                        within(mirror(A), mirror(B), d, p)};
    for (size_t k = 0; k < std::size(got); ++k)
      if (got[k] != v.within) {
        ADD_FAILURE() << "seed " << seed << " iteration " << it << " variant " << k << " at " << p.name
                      << (similar ? " (similarity)" : "") << ": expected " << v.within << (v.tie ? " (tie)" : "")
                      << "; " << describe(P, Q, quarters);
        return out;
      }
  }
  return out;
}

// The oracle itself: distance 0 iff the separating-axis oracle of the intersection test says
// the triangles meet.
TEST(ProximityOracle, DistanceZeroIsIntersection) {
  RandomPairs gen(5, 3);
  int meet = 0;
  for (int it = 0; it < 20000; ++it) {
    ITri P, Q;
    gen.next(P, Q);
    const bool m = sat_oracle_intersect(P, Q);
    meet += m;
    ASSERT_EQ(oracle_within(P, Q, 0).within, m) << describe(P, Q, 0);
  }
  EXPECT_GT(meet, 3000);
}

TEST(ProximityRandom, TinyLatticeAgreesWithOracle) {
  const Outcome o = compare_with_oracle(1, 1, 40000, false);  // coordinates in {-1, 0, 1}
  EXPECT_GT(o.within, 30000);
  EXPECT_GT(o.apart, 4000);
  EXPECT_GT(o.ties, 15000);
}

TEST(ProximityRandom, SmallLatticeAgreesWithOracle) {
  const Outcome o = compare_with_oracle(2, 3, 40000, false);
  EXPECT_GT(o.apart, 6000);
  EXPECT_GT(o.ties, 10000);
}

TEST(ProximityRandom, WiderLatticeAgreesWithOracle) {
  const Outcome o = compare_with_oracle(3, 10, 30000, false);
  EXPECT_GT(o.apart, 4500);
  EXPECT_GT(o.ties, 7000);
}

// The same through the similarity: full-width mantissas, so the double evaluation rounds,
// and the ties stay exact ties that only the exact path can decide.
TEST(ProximityRandom, RotatedLatticesAgreeWithOracle) {
  const Outcome tiny = compare_with_oracle(4, 1, 40000, true);
  EXPECT_GT(tiny.apart, 4000);
  EXPECT_GT(tiny.ties, 15000);
  const Outcome small = compare_with_oracle(5, 3, 40000, true);
  EXPECT_GT(small.apart, 6000);
  EXPECT_GT(small.ties, 10000);
}

// --- hand cases: one ulp decides -----------------------------------------------------------

struct DistanceCase {
  const char* name;
  ITri P, Q;
  int64_t distance;  // exact
};

const ITri T = {IVec{0, 0, 0}, IVec{4, 0, 0}, IVec{0, 4, 0}};

std::vector<DistanceCase> distance_cases() {
  return {
      {"point above the face", T, {IVec{1, 1, 3}, IVec{1, 1, 3}, IVec{1, 1, 3}}, 3},
      {"vertex above the face", T, {IVec{1, 1, 3}, IVec{1, 1, 9}, IVec{2, 1, 9}}, 3},
      {"face below a vertex", {IVec{1, 1, 3}, IVec{1, 1, 9}, IVec{2, 1, 9}}, T, 3},
      {"vertex beside an edge", T, {IVec{2, -3, 4}, IVec{2, -9, 4}, IVec{2, -3, 20}}, 5},
      {"vertex to vertex", T, {IVec{-3, -4, 0}, IVec{-3, -14, 0}, IVec{-13, -4, 0}}, 5},
      {"edges crossing over, skew", {IVec{0, 0, 0}, IVec{4, 0, 0}, IVec{2, 0, -5}},
       {IVec{2, -1, 3}, IVec{2, 1, 3}, IVec{2, 0, 9}}, 3},
      {"edge over an edge and a face", {IVec{0, 0, 0}, IVec{4, 0, 0}, IVec{2, -5, 0}},
       {IVec{2, -1, 3}, IVec{2, 1, 3}, IVec{2, 0, 9}}, 3},
      {"parallel planes", T, {IVec{0, 0, 5}, IVec{4, 0, 5}, IVec{0, 4, 5}}, 5},
      {"coplanar, vertex to vertex", T, {IVec{5, 0, 0}, IVec{9, 0, 0}, IVec{5, 4, 0}}, 1},
      {"coplanar, parallel edges", T, {IVec{0, -2, 0}, IVec{4, -2, 0}, IVec{2, -6, 0}}, 2},
      {"points", {IVec{1, 2, 3}, IVec{1, 2, 3}, IVec{1, 2, 3}}, {IVec{4, 6, 3}, IVec{4, 6, 3}, IVec{4, 6, 3}}, 5},
      {"point and segment", {IVec{0, 0, 0}, IVec{8, 0, 0}, IVec{4, 0, 0}}, {IVec{5, 3, 4}, IVec{5, 3, 4}, IVec{5, 3, 4}},
       5},
      {"parallel segments", {IVec{0, 0, 0}, IVec{4, 0, 0}, IVec{2, 0, 0}}, {IVec{1, 3, 4}, IVec{3, 3, 4}, IVec{2, 3, 4}},
       5},
      {"collinear segments", {IVec{0, 0, 0}, IVec{4, 0, 0}, IVec{2, 0, 0}}, {IVec{7, 0, 0}, IVec{9, 0, 0}, IVec{8, 0, 0}},
       3},
      {"segment over the face", T, {IVec{1, 1, 2}, IVec{2, 1, 2}, IVec{3, 1, 2}}, 2},
  };
}

class ProximityHand : public testing::TestWithParam<DistanceCase> {};

TEST_P(ProximityHand, OneUlpDecidesAtEveryPlacement) {
  const DistanceCase& c = GetParam();
  ASSERT_TRUE(oracle_within(c.P, c.Q, 4 * c.distance).tie) << "the oracle disagrees with the hand distance";
  for (const Placement& p : kPlacements) {
    const float d = place_distance(4 * c.distance, p);
    const float below = std::nextafter(d, 0.0f), above = std::nextafter(d, FLT_MAX);
    EXPECT_TRUE(within(c.P, c.Q, d, p)) << p.name;
    EXPECT_TRUE(within(c.Q, c.P, d, p)) << p.name << ", swapped";
    EXPECT_TRUE(within(c.P, c.Q, above, p)) << p.name;
    EXPECT_FALSE(within(c.P, c.Q, below, p)) << p.name;
    EXPECT_FALSE(within(c.Q, c.P, below, p)) << p.name << ", swapped";
    const ITri P = similarity(c.P), Q = similarity(c.Q);
    const float ds = place_distance(4 * c.distance * kSimilarityScale, p);
    EXPECT_TRUE(within(P, Q, ds, p)) << p.name << ", similarity";
    EXPECT_FALSE(within(P, Q, std::nextafter(ds, 0.0f), p)) << p.name << ", similarity";
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, ProximityHand, testing::ValuesIn(distance_cases()),
                         [](const testing::TestParamInfo<DistanceCase>& info) {
                           return param_name(info.param.name);
                         });

// An irrational distance, sqrt(2), decided by the floats next to it on either side; the side
// of a float d in [1, 2) is known exactly from d = M 2^-23: d^2 >= 2 iff M^2 >= 2^47.
TEST(ProximityFloat, IrrationalDistanceBetweenNeighbouringFloats) {
  const float r = std::sqrt(2.0f);
  const int64_t M = int64_t(std::ldexp(r, 23));  // r = M 2^-23 (r in [1, 2))
  const bool r_covers = __int128(M) * M >= __int128(1) << 47;
  const float lo = r_covers ? std::nextafter(r, 0.0f) : r, hi = r_covers ? r : std::nextafter(r, 2.0f);
  // Hypotenuse x + y = 4 of T and a parallel edge x + y = 6: distance 2 / sqrt(2) = sqrt(2).
  const ITri Q = {IVec{6, 0, 0}, IVec{0, 6, 0}, IVec{6, 6, 0}};
  // A point at (1, 1) off the corner (0, 0) of T's reflection: distance sqrt(2) to a vertex.
  const ITri R = {IVec{-1, -1, 0}, IVec{-1, -1, 0}, IVec{-1, -1, 0}};
  int placements = 0;
  for (const Placement& p : kPlacements) {
    const float scale = std::ldexp(1.0f, p.exponent);
    // Only where the scaled d keep all their bits (not among subnormals).
    if (std::ldexp(lo * scale, -p.exponent) != lo || std::ldexp(hi * scale, -p.exponent) != hi) continue;
    ++placements;
    for (const ITri* other : {&Q, &R}) {
      EXPECT_TRUE(within(T, *other, hi * scale, p)) << p.name;
      EXPECT_FALSE(within(T, *other, lo * scale, p)) << p.name;
    }
  }
  EXPECT_EQ(placements, 6);
}

// The whole float range in one pair: coordinates near 2^127 and below 2^-126, ties that only
// the exact path decides with its largest integers.
TEST(ProximityFloat, ExtremeMagnitudes) {
  const float H = std::ldexp(1.0f, 127), h = std::ldexp(1.0f, 126), tiny = 1e-45f;
  const vec3f a = v3(0, 0, 0), b = v3(H, 0, 0), c = v3(0, H, 0);
  // A point above the face at height 2^126, and one subnormal step below that.
  const vec3f p = v3(tiny, h / 2, h);
  EXPECT_TRUE(triangles_within(a, b, c, p, p, p, h));
  EXPECT_FALSE(triangles_within(a, b, c, p, p, p, std::nextafter(h, 0.0f)));
  // Skew edges crossing over at distance 2^127, coordinates +-2^127 (differences 2^128).
  const vec3f e0 = v3(-H, 0, 0), e1 = v3(H, 0, 0), f0 = v3(tiny, -H, H), f1 = v3(tiny, H, H);
  EXPECT_TRUE(triangles_within(e0, e1, e1, f0, f1, f1, H));
  EXPECT_FALSE(triangles_within(e0, e1, e1, f0, f1, f1, std::nextafter(H, 0.0f)));
  EXPECT_TRUE(triangles_within(e0, e1, e1, f0, f1, f1, FLT_MAX));
  // Subnormal features: two points one and two float steps apart.
  const vec3f s = v3(tiny, 0, 0), t = v3(3 * tiny, 0, 0);
  EXPECT_TRUE(triangles_within(s, s, s, t, t, t, 2 * tiny));
  EXPECT_FALSE(triangles_within(s, s, s, t, t, t, tiny));
  // The limits of d.
  EXPECT_TRUE(triangles_within(a, b, c, e0, e1, e1, 0.0f));
  EXPECT_FALSE(triangles_within(s, s, s, t, t, t, 0.0f));
  EXPECT_TRUE(triangles_within(s, s, s, t, t, t, INFINITY));
  EXPECT_FALSE(triangles_within(s, s, s, t, t, t, -1.0f));
  EXPECT_FALSE(triangles_within(s, s, s, t, t, t, NAN));
}

// Exact evaluations at the largest differences floats allow (2^129): the exact integers of
// every polynomial agree with the filter wherever the filter decides.
TEST(ProximityFloat, ExactPathAtFloatMax) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  int decided = 0;
  for (int it = 0; it < 2000; ++it) {
    vec3f q[4];
    for (vec3f& v : q) v = v3(u(rng) * FLT_MAX, u(rng) * FLT_MAX, u(rng) * FLT_MAX);
    const float d = std::abs(u(rng)) * FLT_MAX;
    auto agree = [&](const auto& f) {
      const BoundedDouble a = f.template evaluate<BoundedDouble>();
      const int exact = f.template evaluate<WideInt>().sign;
      if (a.value > a.bound()) {
        ASSERT_EQ(exact, 1) << it;
      } else if (a.value < -a.bound()) {
        ASSERT_EQ(exact, -1) << it;
      }
      decided += std::abs(a.value) > a.bound();
    };
    agree(proximity::LineLineExcess{q[0], q[1], q[2], q[3], d});
    agree(proximity::PointPlaneExcess{q[0], q[1], q[2], q[3], d});
    agree(proximity::LineParameter{q[0], q[1], q[2], q[3], true});
    agree(proximity::InsideEdge{q[0], q[1], q[2], q[3]});
    agree(proximity::PointLineExcess{q[0], q[1], q[2], d});
  }
  EXPECT_GT(decided, 9000);
}

// --- contact counts ------------------------------------------------------------------------

// Two unit right triangles in parallel planes 1 apart (faces 0, 1), a third 3 away (face 2).
struct Stack {
  std::vector<vec3f> v = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0), v3(0, 0, 1), v3(1, 0, 1),
                          v3(0, 1, 1), v3(0, 0, 4), v3(1, 0, 4), v3(0, 1, 4)};
  std::vector<Tri> faces = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}};
  std::vector<PrimPair> pairs = {{0, 1}, {0, 2}, {1, 2}};
};

TEST(Contacts, DistanceRaisesTheCount) {
  const Stack s;
  EXPECT_EQ(count_true_contacts(s.faces, s.v, s.pairs), 0u);
  EXPECT_EQ(count_true_contacts(s.faces, s.v, s.pairs, 0.999f), 0u);
  EXPECT_EQ(count_true_contacts(s.faces, s.v, s.pairs, 1.0f), 1u);
  EXPECT_EQ(count_true_contacts(s.faces, s.v, s.pairs, 3.0f), 2u);
  EXPECT_EQ(count_true_contacts(s.faces, s.v, s.pairs, 4.0f), 3u);
}

// Face 0 moves from below face 1 to above it within the frame: at neither end do they touch,
// midway they are coplanar and overlap. Face 2 stays 3 above the moving one's start.
TEST(Contacts, IntervalContactsBetweenFrames) {
  const Stack s;
  std::vector<vec3f> previous = s.v, current = s.v;
  for (int k = 0; k < 3; ++k) previous[size_t(k)].z = 0.0f, current[size_t(k)].z = 2.0f;
  EXPECT_EQ(count_true_contacts(s.faces, previous, s.pairs), 0u);
  EXPECT_EQ(count_true_contacts(s.faces, current, s.pairs), 0u);
  EXPECT_EQ(count_interval_contacts(s.faces, previous, current, {{0, 1}}, 0.0f, 2), 1u);  // t = 1/2
  EXPECT_EQ(count_interval_contacts(s.faces, previous, current, {{0, 1}}, 0.0f, 8), 1u);
  // Three substeps sample t = 1/3, 2/3: heights 2/3 and 4/3, a third away from face 1.
  EXPECT_EQ(count_interval_contacts(s.faces, previous, current, {{0, 1}}, 0.0f, 3), 0u);
  EXPECT_EQ(count_interval_contacts(s.faces, previous, current, {{0, 1}}, 0.34f, 3), 1u);
  // Face 2 at z = 4: face 0 comes within 2 of it only at the end of the interval.
  EXPECT_EQ(count_interval_contacts(s.faces, previous, current, {{0, 2}}, 2.0f, 1), 1u);
  EXPECT_EQ(count_interval_contacts(s.faces, previous, current, {{0, 2}}, 1.99f, 8), 0u);
  // Both ends exact: no motion means the frame's own contacts.
  EXPECT_EQ(count_interval_contacts(s.faces, s.v, s.v, s.pairs, 1.0f, 8), count_true_contacts(s.faces, s.v, s.pairs, 1.0f));
  EXPECT_THROW(count_interval_contacts(s.faces, previous, current, s.pairs, 0.0f, 0), Error);
}

}  // namespace
}  // namespace cdb
