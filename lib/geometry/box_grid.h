#pragma once
// The 16-bit box grid of --box-precision q16 (docs/design.md "Speed/accuracy knobs"): per
// axis 65536 lines spanning the frame's vertex bounds; a triangle box snaps outward onto
// it, lo to the line at or below, hi to the line at or above, as a 16-bit box format would
// store it. Lines are computed in double (a span of two floats near +-3e38 overflows
// float) and converted to float rounding outward; a min/max with the exact box guards the
// rest, so a snapped box contains the exact one by construction.
#include <cmath>
#include <cstdint>
#include <limits>

#include "cdbench/core/aabb.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/outward_rounding.h"
#include "cdbench/core/vec.h"

namespace cdb {

// Grid indices 0..kBoxGridMaxIndex: 16 bits.
inline constexpr double kBoxGridMaxIndex = 65535.0;

// One axis of the grid: line k at origin + k * cell (in double, unfused).
struct BoxGridAxis {
  double origin = 0.0;
  double cell = 0.0;      // 0: the frame has no extent on this axis (or no vertices): no snapping
  double inv_cell = 0.0;  // kBoxGridMaxIndex / span: a first guess of the index, corrected after
};

struct BoxGrid {
  BoxGridAxis x, y, z;
};

CDB_HD_INLINE BoxGridAxis box_grid_axis(float lo, float hi) {
  BoxGridAxis a;
  const double span = static_cast<double>(hi) - static_cast<double>(lo);
  // Not > 0 also covers empty bounds (lo = +inf, hi = -inf): nothing to snap. The span of
  // two finite floats is finite in double.
  if (!(span > 0.0) || !(span < std::numeric_limits<double>::infinity())) return a;
  a.origin = lo;
  a.cell = span / kBoxGridMaxIndex;
  a.inv_cell = kBoxGridMaxIndex / span;
  return a;
}

CDB_HD_INLINE BoxGrid box_grid(const Aabb<float>& bounds) {
  return {box_grid_axis(bounds.lo.x, bounds.hi.x), box_grid_axis(bounds.lo.y, bounds.hi.y),
          box_grid_axis(bounds.lo.z, bounds.hi.z)};
}

CDB_HD_INLINE double box_grid_line(const BoxGridAxis& a, double k) { return a.origin + mul_unfused(k, a.cell); }

// Index of the last line at or below v (clamped to the grid). The guess from inv_cell is
// off by at most one; the two corrections make line(k) <= v < line(k + 1) hold as the
// lines are actually computed.
CDB_HD_INLINE double box_grid_floor(const BoxGridAxis& a, float v) {
  double k = floor(mul_unfused(static_cast<double>(v) - a.origin, a.inv_cell));
  k = k < 0.0 ? 0.0 : k > kBoxGridMaxIndex ? kBoxGridMaxIndex : k;
  if (k > 0.0 && box_grid_line(a, k) > v) k -= 1.0;
  if (k < kBoxGridMaxIndex && box_grid_line(a, k + 1.0) <= v) k += 1.0;
  return k;
}

// lo snapped down, hi snapped up, each never inside the exact value.
CDB_HD_INLINE float snap_down(const BoxGridAxis& a, float lo) {
  if (a.cell == 0.0) return lo;
  return min_of(float_at_or_below(box_grid_line(a, box_grid_floor(a, lo))), lo);
}

CDB_HD_INLINE float snap_up(const BoxGridAxis& a, float hi) {
  if (a.cell == 0.0) return hi;
  double k = box_grid_floor(a, hi);
  if (box_grid_line(a, k) < hi && k < kBoxGridMaxIndex) k += 1.0;
  return max_of(float_at_or_above(box_grid_line(a, k)), hi);
}

CDB_HD_INLINE void snap_box_outward(const BoxGrid& g, vec4f& lo, vec4f& hi) {
  lo = {snap_down(g.x, lo.x), snap_down(g.y, lo.y), snap_down(g.z, lo.z), 0.0f};
  hi = {snap_up(g.x, hi.x), snap_up(g.y, hi.y), snap_up(g.z, hi.z), 0.0f};
}

// The frame's vertex bounds, reduced on the executor: each vertex, and with swept boxes
// also its previous position (`prev`, may be null), so the grid spans every box it snaps.
struct VertexBoundsFn {
  const vec3f* vertices;
  const vec3f* prev;
  CDB_HD Aabb<float> operator()(uint32_t i) const {
    const vec3f v = vertices[i];
    Aabb<float> b{{v.x, v.y, v.z, 0.0f}, {v.x, v.y, v.z, 0.0f}};
    if (prev) {
      const vec3f p = prev[i];
      b.grow(vec4f{p.x, p.y, p.z, 0.0f});
    }
    return b;
  }
};

// One thread: the grid from the reduced bounds, on the executor (no read-back).
struct BoxGridFn {
  const Aabb<float>* bounds;
  BoxGrid* grid;
  CDB_HD void operator()(uint32_t) const { *grid = box_grid(*bounds); }
};

}  // namespace cdb
