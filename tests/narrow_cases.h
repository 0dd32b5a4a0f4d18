#pragma once
// Shared by the narrow-phase tests (host and GPU): an independent exact triangle
// intersection oracle in integer arithmetic, exact float placements of integer triangles,
// and a generator of small-integer triangle pairs rich in degeneracies.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "cdbench/core/vec.h"

namespace cdb {

// --- independent oracle: separating axes, exact in int64 -----------------------------------

struct IVec {
  int64_t x, y, z;
};
inline IVec operator-(IVec a, IVec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline IVec cross(IVec a, IVec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline int64_t dot(IVec a, IVec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

using ITri = std::array<IVec, 3>;

// Do the closed convex hulls of P and Q (each three points, any of them equal or collinear)
// share a point? They are disjoint iff the origin is outside C = P - Q = hull{p_i - q_j};
// then the point c* of C nearest the origin is nonzero, c* separates, and c* lies in the
// relative interior of a face F of C:
//  - F a vertex: c* is one of R = {p_i - q_j}                              (axes: R)
//  - F an edge, direction w, through the vertex r: c* is parallel to (w x r) x w; an edge of
//    the Minkowski difference is parallel to an edge of P or of Q, so w is in
//    E = {p_i - p_j} u {q_i - q_j}, and r in R                    (axes: (w x r) x w, w in E, r in R)
//  - F a 2-face (C itself when C is flat): c* is parallel to its normal, which is spanned by
//    two directions of E                                            (axes: u x v, u, v in E)
// So if the hulls are disjoint, one of these axes a has max over P of a.p < min over Q of
// a.q or the reverse; if they intersect, no axis can (a common point projects into both).
// Zero axes never separate. Coordinates up to 2^10 keep every value below 2^62.
inline bool sat_oracle_intersect(const ITri& P, const ITri& Q) {
  std::vector<IVec> E, R, axes;
  for (int i = 0; i < 3; ++i)
    for (int j = i + 1; j < 3; ++j) {
      E.push_back(P[j] - P[i]);
      E.push_back(Q[j] - Q[i]);
    }
  for (const IVec& p : P)
    for (const IVec& q : Q) R.push_back(p - q);
  axes = R;
  for (size_t i = 0; i < E.size(); ++i)
    for (size_t j = i + 1; j < E.size(); ++j) axes.push_back(cross(E[i], E[j]));
  for (const IVec& w : E)
    for (const IVec& r : R) axes.push_back(cross(cross(w, r), w));
  for (const IVec& a : axes) {
    int64_t p_lo = dot(a, P[0]), p_hi = p_lo, q_lo = dot(a, Q[0]), q_hi = q_lo;
    for (int k = 1; k < 3; ++k) {
      p_lo = std::min(p_lo, dot(a, P[k]));
      p_hi = std::max(p_hi, dot(a, P[k]));
      q_lo = std::min(q_lo, dot(a, Q[k]));
      q_hi = std::max(q_hi, dot(a, Q[k]));
    }
    if (p_hi < q_lo || q_hi < p_lo) return false;
  }
  return true;
}

// --- float copies: (x + offset) * 2^exponent is exact in float for |x + offset| < 2^24 ----

struct Placement {
  int64_t offset;
  int exponent;
  const char* name;
};
const Placement kPlacements[] = {
    {0, 0, "unit"},
    {0, 100, "2^100 (~1e30)"},
    {0, -100, "2^-100 (~1e-30)"},
    {0, -140, "2^-140 (float subnormals)"},
    {1 << 20, 0, "offset 2^20"},
    {1 << 20, -3, "offset 2^17, features 1/8"},
    {-(1 << 19), 90, "offset -2^109"},
    {(1 << 22) + 12345, -130, "offset ~2^-108, features 2^-130"},
};

inline float place(int64_t x, const Placement& p) { return std::ldexp(float(x + p.offset), p.exponent); }
inline vec3f place(IVec v, const Placement& p) { return {place(v.x, p), place(v.y, p), place(v.z, p)}; }

// Small-integer triangles with many degeneracies: shared vertices, coplanar pairs, points,
// segments and touching configurations, each drawn with its own probability.
struct RandomPairs {
  std::mt19937_64 rng;
  int range;
  explicit RandomPairs(uint64_t seed, int r) : rng(seed), range(r) {}
  int64_t coord() { return std::uniform_int_distribution<int64_t>(-range, range)(rng); }
  IVec point() { return {coord(), coord(), coord()}; }
  bool chance(int percent) { return std::uniform_int_distribution<int>(0, 99)(rng) < percent; }
  void next(ITri& P, ITri& Q) {
    for (auto& v : P) v = point();
    for (auto& v : Q) v = point();
    if (chance(30))
      for (auto* t : {&P, &Q})
        for (auto& v : *t) v.z = 0;  // coplanar pair
    if (chance(15)) Q[0] = P[std::uniform_int_distribution<int>(0, 2)(rng)];  // shared vertex
    if (chance(15)) degenerate(chance(50) ? P : Q);
    if (chance(5)) degenerate(P), degenerate(Q);
  }
  void degenerate(ITri& t) {
    if (chance(30)) {
      t[1] = t[2] = t[0];  // a point
      return;
    }
    // Collinear: t2 = t0 + k (t1 - t0) with k in [-2, 4].
    const IVec d = t[1] - t[0];
    const int64_t k = std::uniform_int_distribution<int64_t>(-2, 4)(rng);
    t[2] = {t[0].x + k * d.x, t[0].y + k * d.y, t[0].z + k * d.z};
    if (chance(20)) t[1] = t[0];  // two equal, the third apart
  }
};

}  // namespace cdb
