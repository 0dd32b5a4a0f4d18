#pragma once
// The first reduction of the cell baselines (grid and hash), from which each sizes its
// cells: the scene's bounds and the sum over the boxes of their widths. Widths and extents
// are in double: those of 1e38-scale boxes overflow float. A box side at +-inf (a margin
// past float range) counts as +-FLT_MAX (cell_coord.h finite_bound), so the bounds, the
// widths and the cells sized from them are finite: a scene's bounds span at most
// 2 FLT_MAX, which double holds.
#include <cstdint>
#include <limits>

#include "baselines/common/cell_coord.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

// The extent of a box along one axis, from lo to hi, of its finite bounds.
template <class Real>
CDB_HD_INLINE double finite_extent(Real lo, Real hi) {
  return double(finite_bound(hi)) - double(finite_bound(lo));
}

// The width of a box: its largest extent.
template <class Real>
CDB_HD_INLINE double box_width(const vec4<Real>& lo, const vec4<Real>& hi) {
  return max_of(finite_extent(lo.x, hi.x), max_of(finite_extent(lo.y, hi.y), finite_extent(lo.z, hi.z)));
}

struct SceneStats {
  double width_sum;
  float lo[3], hi[3];
};

// The scene's largest extent.
CDB_HD_INLINE double scene_extent(const SceneStats& s) {
  double extent = 0.0;
  for (int k = 0; k < 3; ++k) extent = max_of(extent, double(s.hi[k]) - double(s.lo[k]));
  return extent;
}

struct SceneStatsOp {
  CDB_HD SceneStats operator()(const SceneStats& a, const SceneStats& b) const {
    SceneStats r;
    r.width_sum = a.width_sum + b.width_sum;
    for (int k = 0; k < 3; ++k) {
      r.lo[k] = min_of(a.lo[k], b.lo[k]);
      r.hi[k] = max_of(a.hi[k], b.hi[k]);
    }
    return r;
  }
  static SceneStats identity() {
    const float inf = std::numeric_limits<float>::infinity();
    return {0.0, {inf, inf, inf}, {-inf, -inf, -inf}};
  }
};

struct SceneStatsFn {
  const vec4f* lo;
  const vec4f* hi;
  CDB_HD SceneStats operator()(uint32_t i) const {
    const vec4f a = lo[i], b = hi[i];
    return {box_width(a, b),
            {finite_bound(a.x), finite_bound(a.y), finite_bound(a.z)},
            {finite_bound(b.x), finite_bound(b.y), finite_bound(b.z)}};
  }
};

}  // namespace cdb
