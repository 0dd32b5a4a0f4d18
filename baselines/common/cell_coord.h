#pragma once
// The cell coordinate of the cell baselines (grid and hash): the one function that both
// registration (which cells a box is entered in) and the ownership rule (which cell
// reports a pair, home_cell.h) go through. Their exactness needs only that it is monotone
// non-decreasing in x: then every point of a box [lo, hi] has its coordinate between
// those of lo and hi, so the cell range of a box holds every cell the box touches.
//
// t = x * s - origin * s, clamped to [0, kMaxCellCoord] and truncated. Each step is
// monotone in x for s >= 0: a clamp of x to the finite floats, a product by a non-negative
// constant rounded to nearest, the subtraction of a constant, a clamp, a truncation. The
// first clamp gives a box bound that overflowed to +-inf (a margin added to a box at
// FLT_MAX, rounded outward) the cell of +-FLT_MAX, so every coordinate of a box lies in the
// range its scene's finite bounds span (finite_bound below) and no inf - inf turns into
// NaN. Scaling before subtracting keeps t finite where x - origin would overflow (boxes
// reaching +-3e38); with s a power of two (the grid's cells) both products are exact short
// of the subnormal range and only the subtraction rounds. The products are never fused
// into an FMA (mul_unfused): the same inputs give the same cell in every kernel and on the
// host. Overflowing products stay monotone: origin * s = +inf maps every x to 0 (-inf, or
// NaN from inf - inf), origin * s = -inf maps every x to the top; NaN, like every t <= 0,
// maps to 0.
#include <cstdint>
#include <limits>

#include "cdbench/core/hd.h"
#include "cdbench/core/outward_rounding.h"
#include "cdbench/core/vec.h"

namespace cdb {

// Cells per axis are at most 2^kCellAxisBits: three coordinates pack into 60 bits.
inline constexpr uint32_t kCellAxisBits = 20;
inline constexpr uint32_t kMaxCellCoord = (1u << kCellAxisBits) - 1;

// x clamped to [-max, max] of its type: the bound the cell baselines give a box side that
// overflowed to an infinity (scene bounds, widths and cell coordinates alike).
template <class Real>
CDB_HD_INLINE Real finite_bound(Real x) {
  constexpr Real big = std::numeric_limits<Real>::max();
  return min_of(max_of(x, -big), big);
}

// The cell coordinate of x along an axis whose cells start at `origin`, each 1 / inv_cell
// wide (inv_cell >= 0).
template <class Real>
CDB_HD_INLINE uint32_t cell_coord(Real x, Real origin, Real inv_cell) {
  const Real t = mul_unfused(finite_bound(x), inv_cell) - mul_unfused(origin, inv_cell);
  return t > Real(0) ? static_cast<uint32_t>(min_of(t, Real(kMaxCellCoord))) : 0u;
}

}  // namespace cdb
