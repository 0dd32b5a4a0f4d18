#pragma once
// Exact sums of doubles as floating-point expansions (Shewchuk, "Adaptive Precision
// Floating-Point Arithmetic and Fast Robust Geometric Predicates", DCG 18, 1997, §2).
//
// An expansion is a list of doubles, nonoverlapping and in increasing magnitude, whose exact
// sum is the value it stands for; its sign is the sign of its last (largest) nonzero
// component. two_sum and two_product are exact (no rounding is lost) in IEEE binary64 with
// round-to-nearest as long as nothing overflows or underflows; the predicates that use them
// (predicates.h) keep every value far inside the double range. Neither function contains a
// product followed by a sum, so contraction into FMA by the compiler cannot change them.
#include <cmath>

#include "cdbench/core/hd.h"

namespace cdb {

// s + e == a + b exactly, s = fl(a + b) (Knuth's Two-Sum: no ordering of |a|, |b| needed).
CDB_HD_INLINE void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double b_virtual = s - a;
  const double a_virtual = s - b_virtual;
  e = (a - a_virtual) + (b - b_virtual);
}

// p + e == a * b exactly, p = fl(a * b): the FMA computes a * b - p with one rounding, and
// that difference is representable.
CDB_HD_INLINE void two_product(double a, double b, double& p, double& e) {
  p = a * b;
  e = fma(a, b, -p);
}

// Adds b to the expansion h[0..n) in place (Shewchuk's Grow-Expansion with zero
// elimination); returns the new length, at most n + 1.
CDB_HD_INLINE int grow_expansion(double* h, int n, double b) {
  double q = b;
  int m = 0;
  for (int i = 0; i < n; ++i) {
    double s, e;
    two_sum(q, h[i], s, e);
    q = s;
    if (e != 0.0) h[m++] = e;
  }
  if (q != 0.0) h[m++] = q;
  return m;
}

// Sign (-1, 0, 1) of the exact sum of terms[0..n), n <= N.
template <int N>
CDB_HD_INLINE int sign_of_exact_sum(const double (&terms)[N], int n) {
  double h[N];
  int m = 0;
  for (int i = 0; i < n; ++i) m = grow_expansion(h, m, terms[i]);
  if (m == 0) return 0;
  return h[m - 1] > 0.0 ? 1 : -1;
}

}  // namespace cdb
