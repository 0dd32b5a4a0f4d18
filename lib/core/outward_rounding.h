#pragma once
// Sums and conversions rounded toward -inf or +inf instead of to nearest, for box bounds
// that must contain the real-valued box they stand for (docs/design.md "Speed/accuracy
// knobs"). Plain IEEE operations only, no rounding-mode switch and no multiplication (so
// nothing a compiler could fuse into an FMA): the host and CUDA kernels give identical bits.
// Subnormals must not be flushed to zero (no fast-math on either side).
#include <cmath>
#include <limits>

#include "cdbench/core/hd.h"

namespace cdb {

// The rounding error of s = a + b (rounded to nearest): (a + b) - s exactly, by Knuth's
// TwoSum, exact for any finite a, b whose sum does not overflow.
CDB_HD_INLINE float two_sum_error(float a, float b, float s) {
  const float b_part = s - a;
  const float a_part = s - b_part;
  return (a - a_part) + (b - b_part);
}

// The largest float at or below the real a - b (b >= 0).
CDB_HD_INLINE float sub_round_down(float a, float b) {
  const float s = a - b;
  // An overflow to -inf is already at or below; TwoSum needs a finite sum.
  if (!(s > -std::numeric_limits<float>::infinity())) return s;
  return two_sum_error(a, -b, s) < 0.0f ? nextafterf(s, -std::numeric_limits<float>::infinity()) : s;
}

// The smallest float at or above the real a + b (b >= 0).
CDB_HD_INLINE float add_round_up(float a, float b) {
  const float s = a + b;
  if (!(s < std::numeric_limits<float>::infinity())) return s;
  return two_sum_error(a, b, s) > 0.0f ? nextafterf(s, std::numeric_limits<float>::infinity()) : s;
}

// The largest float at or below x (-inf below -FLT_MAX).
CDB_HD_INLINE float float_at_or_below(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) > x ? nextafterf(f, -std::numeric_limits<float>::infinity()) : f;
}

// The smallest float at or above x (+inf above FLT_MAX).
CDB_HD_INLINE float float_at_or_above(double x) {
  const float f = static_cast<float>(x);
  return static_cast<double>(f) < x ? nextafterf(f, std::numeric_limits<float>::infinity()) : f;
}

// a * b rounded to nearest and never fused with a following addition: CUDA contracts
// a * b + c into an FMA by default, which would make device results differ from the host's.
CDB_HD_INLINE double mul_unfused(double a, double b) {
#if defined(__CUDA_ARCH__)
  return __dmul_rn(a, b);
#else
  return a * b;
#endif
}
CDB_HD_INLINE float mul_unfused(float a, float b) {
#if defined(__CUDA_ARCH__)
  return __fmul_rn(a, b);
#else
  return a * b;
#endif
}

}  // namespace cdb
