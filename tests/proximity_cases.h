#pragma once
// Shared by the proximity tests (host and GPU): an independent exact oracle for "the closed
// triangles P and Q (small integer points) lie within d = k/4 of each other", in __int128,
// and an exact similarity that turns small integer points into full-width float mantissas.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>

#include "narrow_cases.h"

namespace cdb {

// The oracle's verdict; `tie` when the distance is exactly d.
struct ProximityVerdict {
  bool within = false, tie = false;
};

namespace oracle_detail {

using i128 = __int128;

inline i128 checked_mul(i128 a, i128 b) {
  i128 r;
  if (__builtin_mul_overflow(a, b, &r)) throw std::overflow_error("proximity oracle: __int128 overflow");
  return r;
}
inline i128 checked_add(i128 a, i128 b) {
  i128 r;
  if (__builtin_add_overflow(a, b, &r)) throw std::overflow_error("proximity oracle: __int128 overflow");
  return r;
}

// Determinant of the n x n matrix g (n <= 3), column `replaced` (if >= 0) taken from b.
inline i128 det(const i128 g[3][3], int n, int replaced = -1, const i128* b = nullptr) {
  auto at = [&](int i, int j) { return j == replaced ? b[i] : g[i][j]; };
  if (n == 1) return at(0, 0);
  if (n == 2) return checked_add(checked_mul(at(0, 0), at(1, 1)), -checked_mul(at(0, 1), at(1, 0)));
  i128 s = 0;
  for (int j = 0; j < 3; ++j) {
    const i128 minor = checked_add(checked_mul(at(1, (j + 1) % 3), at(2, (j + 2) % 3)),
                                   -checked_mul(at(1, (j + 2) % 3), at(2, (j + 1) % 3)));
    s = checked_add(s, checked_mul(at(0, j), minor));
  }
  return s;
}

}  // namespace oracle_detail

// Distance between the closed convex hulls of P and Q against d = quarters / 4, exactly.
// Method (independent of lib/narrow/proximity.h): for every pair of nonempty vertex subsets
// F of P and G of Q, minimize |x - y|^2 over x in aff(F), y in aff(G) by the normal
// equations, solved by Cramer's rule in integers; a candidate is the minimum when that system
// is nonsingular and its barycentric coordinates are >= 0 (x, y in the closed faces). Every
// candidate is a distance between points of the hulls; the true distance is one: a closest
// pair whose supporting faces F, G have the least total dimension has affinely independent
// vertices and a nonsingular system (a null direction would slide the pair, at constant
// distance, onto a smaller face), and it is the unique minimizer over aff(F) x aff(G).
// Intersection is the case distance 0.
inline ProximityVerdict oracle_within(const ITri& P, const ITri& Q, int64_t quarters) {
  using namespace oracle_detail;
  ProximityVerdict verdict;
  bool below = false, equal = false;
  for (int fs = 1; fs < 8; ++fs)
    for (int gs = 1; gs < 8; ++gs) {
      IVec f[3], g[3];
      int nf = 0, ng = 0;
      for (int i = 0; i < 3; ++i) {
        if (fs >> i & 1) f[nf++] = P[i];
        if (gs >> i & 1) g[ng++] = Q[i];
      }
      const int n = nf - 1 + ng - 1;
      if (n > 3) continue;
      IVec cols[3];
      int c = 0;
      for (int i = 1; i < nf; ++i) cols[c++] = f[i] - f[0];
      for (int j = 1; j < ng; ++j) cols[c++] = g[0] - g[j];
      const IVec base = f[0] - g[0];
      i128 gram[3][3] = {}, rhs[3] = {};
      for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) gram[i][j] = dot(cols[i], cols[j]);
        rhs[i] = -i128(dot(cols[i], base));
      }
      i128 den = n == 0 ? 1 : det(gram, n);
      if (den == 0) continue;
      i128 z[3];
      for (int i = 0; i < n; ++i) z[i] = det(gram, n, i, rhs);
      if (den < 0) {
        den = -den;
        for (int i = 0; i < n; ++i) z[i] = -z[i];
      }
      // Barycentric feasibility: alpha_i = z_i / den >= 0, sum over each side <= 1.
      bool feasible = true;
      i128 sum_f = 0, sum_g = 0;
      for (int i = 0; i < n; ++i) {
        feasible = feasible && z[i] >= 0;
        (i < nf - 1 ? sum_f : sum_g) += z[i];
      }
      if (!feasible || sum_f > den || sum_g > den) continue;
      // den * (x - y) = den * base + sum z_i cols_i; compare |.|^2 with d^2 den^2.
      i128 w[3] = {checked_mul(den, base.x), checked_mul(den, base.y), checked_mul(den, base.z)};
      for (int i = 0; i < n; ++i) {
        w[0] = checked_add(w[0], checked_mul(z[i], cols[i].x));
        w[1] = checked_add(w[1], checked_mul(z[i], cols[i].y));
        w[2] = checked_add(w[2], checked_mul(z[i], cols[i].z));
      }
      i128 lhs = 0;
      for (const i128 wk : w) lhs = checked_add(lhs, checked_mul(checked_mul(wk, wk), 16));
      const i128 rhs_d = checked_mul(checked_mul(den, den), i128(quarters) * quarters);
      below = below || lhs < rhs_d;
      equal = equal || lhs == rhs_d;
    }
  verdict.within = below || equal;
  verdict.tie = equal && !below;
  return verdict;
}

// d = k / 4 right at the decision for a pair of `range` lattice triangles: k* the least k
// within (by bisection on the oracle; a tie when the distance is k* / 4), and k one of
// k* - 1, k*, k* + 1 (never below 0), drawn from `rng`.
inline int64_t quarters_near_decision(const ITri& P, const ITri& Q, int range, std::mt19937_64& rng) {
  int64_t lo = 0, hi = 14 * int64_t(range);  // 14 range / 4 > the lattice's diameter 2 sqrt(3) range
  while (lo < hi) {
    const int64_t mid = (lo + hi) / 2;
    if (oracle_within(P, Q, mid).within)
      hi = mid;
    else
      lo = mid + 1;
  }
  return std::max<int64_t>(0, lo + std::uniform_int_distribution<int64_t>(-1, 1)(rng));
}

// d = quarters / 4 at a placement's scale (offsets do not change distances): exact in float
// for the placements of narrow_cases.h and quarters < 2^24.
inline float place_distance(int64_t quarters, const Placement& p) {
  return std::ldexp(float(quarters), p.exponent - 2);
}

// An integer similarity, 27625 times a rotation (four Pythagorean rotations about different
// axes: 3-4-5, 5-12-13, 8-15-17, 7-24-25): it keeps every distance ratio, coplanarity,
// parallelism and shared vertex exactly, and spreads small integers over ~20-bit mantissas,
// so the filters' double products round.
inline constexpr int64_t kSimilarityScale = 5 * 13 * 17 * 25;

inline IVec similarity(IVec v) {
  auto rotate = [](IVec p, int axis, int64_t a, int64_t b) {  // scaled rotation by (a, b)
    int64_t* c[3] = {&p.x, &p.y, &p.z};
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    const int64_t ci = *c[i], cj = *c[j], k = a * a + b * b;
    const int64_t h = int64_t(std::llround(std::sqrt(double(k))));
    *c[i] = a * ci - b * cj;
    *c[j] = b * ci + a * cj;
    *c[axis] *= h;
    return p;
  };
  v = rotate(v, 2, 3, 4);
  v = rotate(v, 0, 5, 12);
  v = rotate(v, 1, 8, 15);
  return rotate(v, 2, 7, 24);
}

inline ITri similarity(const ITri& t) { return {similarity(t[0]), similarity(t[1]), similarity(t[2])}; }

}  // namespace cdb
