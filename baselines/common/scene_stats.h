#pragma once
// The first reduction of the cell baselines (grid and hash), from which each sizes its
// cells: the scene's bounds and the sum over the boxes of their widths. Widths and extents
// are in double: those of 1e38-scale boxes overflow float.
#include <cstdint>
#include <limits>

#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

// The width of a box: its largest extent.
template <class Real>
CDB_HD_INLINE double box_width(const vec4<Real>& lo, const vec4<Real>& hi) {
  const double ex = double(hi.x) - double(lo.x), ey = double(hi.y) - double(lo.y),
               ez = double(hi.z) - double(lo.z);
  return max_of(ex, max_of(ey, ez));
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
    return {box_width(a, b), {a.x, a.y, a.z}, {b.x, b.y, b.z}};
  }
};

}  // namespace cdb
