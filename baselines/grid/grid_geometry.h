#pragma once
// Geometry of the uniform-grid baseline (issue 6): cell size and levels, chosen on the
// device every frame from the triangle boxes, with no host round trip.
//
// Cell-size rule. The width of a box is its largest extent. Level 0's cell is the trimmed
// mean width t, rounded up to a power of two: c0 = 2^ceil(log2 t), so t <= c0 < 2t. The
// mean is trimmed to the boxes at most kGridTrim times the plain mean wide; by Markov's
// inequality that keeps at least 3/4 of the boxes, and it drops the few scene-spanning
// triangles that would otherwise inflate a plain mean (kDet's rule) and with it every
// cell. A power of two makes x / cell a product by an exact power of two: only the
// subtraction of the origin rounds. c0 is also at least 2^-(kCellAxisBits-1) of the
// scene's largest extent, so no axis needs more than 2^kCellAxisBits cells.
//
// Levels, the adaptive part. OTG (Wang, Lin, Zhang, Tang 2014) subdivides space in two
// levels so that a non-uniform scene does not force one cell size on every primitive; for
// deforming meshes the non-uniformity that hurts a grid is of size (cloth beside a coarse
// rigid body, a few scene-spanning triangles), so the levels here are by size, as in
// hierarchical grids: level l has cell c0 * 2^l, and a box of width w lives on the finest
// level whose cell is at least w / 2. There it covers at most 3 cells per axis, 27 in all,
// whatever its size. The top level's cell is at least half the scene, so every box has a
// level, and no box is ever left out or given an unbounded number of cells. A scene of
// equal triangles uses level 0 only.
//
// Every level is a lattice of the cell baselines' common pieces (baselines/common): its
// cell coordinates come from the one monotone cell_coord(), which is all the exactness
// argument of the pair rule (cell_pairs.h) needs.
#include <cmath>
#include <cstdint>

#include "baselines/common/cell_coord.h"
#include "baselines/common/cell_range.h"
#include "baselines/common/scene_stats.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

inline constexpr double kGridTrim = 4.0;
// 2^-126 is the smallest normal float and 2^130 exceeds any finite scene's extent; within
// these the inverse cell 2^-e is an exact float (normal or subnormal, never zero).
inline constexpr int kGridMinCellExp = -126;
inline constexpr int kGridMaxCellExp = 130;
// Levels span 2^(kCellAxisBits-1) (level 0 at least that fraction of the scene, the top at
// least half of it): kCellAxisBits - 1 of them at most.
inline constexpr uint32_t kGridMaxLevels = kCellAxisBits - 1;
// A box on its level covers at most 3 cells per axis; the level choice still checks the
// product against this bound and moves a box up while it is exceeded (rounding). The top
// level holds every box: its cell is at least half the scene, so the whole scene spans at
// most 3 cells per axis there.
inline constexpr uint32_t kGridMaxCellsPerBox = 27;

// ceil(log2 x) for finite x > 0, exact (frexp, no rounding).
CDB_HD_INLINE int ceil_log2(double x) {
  int e = 0;
  const double f = frexp(x, &e);  // x = f * 2^e, f in [0.5, 1)
  return f == 0.5 ? e - 1 : e;
}

// Sum and count of the widths of the boxes at most kGridTrim mean widths wide (the second
// reduction; it needs the first's, SceneStats, for the mean).
struct TrimmedWidths {
  double sum;
  unsigned long long count;
};

struct TrimmedWidthsOp {
  CDB_HD TrimmedWidths operator()(const TrimmedWidths& a, const TrimmedWidths& b) const {
    return {a.sum + b.sum, a.count + b.count};
  }
};

struct TrimmedWidthsFn {
  const vec4f* lo;
  const vec4f* hi;
  const SceneStats* scene;
  uint32_t n;
  CDB_HD TrimmedWidths operator()(uint32_t i) const {
    const double w = box_width(lo[i], hi[i]);
    const double limit = kGridTrim * (scene->width_sum / n);
    return w <= limit ? TrimmedWidths{w, 1ull} : TrimmedWidths{0.0, 0ull};
  }
};

struct GridLevel {
  float inv_cell;           // 2^-e exactly, e = the level's cell exponent
  uint32_t dims[3];         // cells per axis
  uint64_t base;  // first key of the level; its keys are [base, base + cells)
};

struct GridLayout {
  float origin[3];
  int cell_exp;  // level 0's cell is 2^cell_exp
  uint32_t levels;
  GridLevel level[kGridMaxLevels];
  uint64_t key_space;  // every key is below it
};

// Level l as a lattice: the scene's origin, the level's cell.
CDB_HD_INLINE CellLattice<float> level_lattice(const GridLayout& p, uint32_t l) {
  return {{p.origin[0], p.origin[1], p.origin[2]}, p.level[l].inv_cell};
}

CDB_HD_INLINE CellRange grid_range(const GridLayout& p, uint32_t l, const vec4f& lo,
                                   const vec4f& hi) {
  return cell_range(level_lattice(p, l), lo, hi);
}

CDB_HD_INLINE uint64_t grid_key(const GridLayout& p, uint32_t l, const CellCoords& c) {
  const GridLevel& g = p.level[l];
  return g.base + c.x + uint64_t(g.dims[0]) * (c.y + uint64_t(g.dims[1]) * c.z);
}

// The level a box of width w starts from: the finest whose cell is at least w / 2.
CDB_HD_INLINE uint32_t level_of_width(const GridLayout& p, double w) {
  if (!(w > 0.0)) return 0;
  const int l = ceil_log2(w) - p.cell_exp - 1;
  return l <= 0 ? 0u : min_of(uint32_t(l), p.levels - 1);
}

// First index in [a, b) of ascending keys whose key is not below `key`.
CDB_HD_INLINE uint32_t lower_bound_key(const uint64_t* keys, uint32_t a, uint32_t b,
                                       uint64_t key) {
  while (a < b) {
    const uint32_t m = a + (b - a) / 2;
    if (keys[m] < key)
      a = m + 1;
    else
      b = m;
  }
  return a;
}

CDB_HD_INLINE uint32_t bit_width(uint64_t v) {
  uint32_t b = 0;
  while (v) {
    ++b;
    v >>= 1;
  }
  return b;
}

// One thread: the rule above, the levels' dimensions and key ranges, and the key bits the
// sort needs (written for the host's one read-back).
struct GridLayoutFn {
  const SceneStats* scene;
  const TrimmedWidths* trimmed;
  GridLayout* params;
  unsigned long long* key_bits;
  CDB_HD void operator()(uint32_t) const {
    const SceneStats s = *scene;
    const TrimmedWidths t = *trimmed;
    const double extent = scene_extent(s);
    const int scene_exp = extent > 0.0 ? ceil_log2(extent) : kGridMinCellExp;
    const double mean = t.count > 0 ? t.sum / double(t.count) : 0.0;
    int e0 = mean > 0.0 ? ceil_log2(mean) : kGridMinCellExp;
    e0 = max_of(e0, scene_exp - int(kCellAxisBits - 1));
    e0 = min_of(max_of(e0, kGridMinCellExp), kGridMaxCellExp);
    const int top = min_of(max_of(scene_exp - 1, e0), kGridMaxCellExp);
    GridLayout* p = params;
    for (int k = 0; k < 3; ++k) p->origin[k] = s.lo[k];
    p->cell_exp = e0;
    p->levels = min_of(uint32_t(top - e0 + 1), kGridMaxLevels);
    uint64_t base = 0;
    for (uint32_t l = 0; l < p->levels; ++l) {
      GridLevel& g = p->level[l];
      g.inv_cell = ldexpf(1.0f, -(e0 + int(l)));
      for (int k = 0; k < 3; ++k) g.dims[k] = cell_coord(s.hi[k], s.lo[k], g.inv_cell) + 1;
      g.base = base;
      base += uint64_t(g.dims[0]) * g.dims[1] * g.dims[2];
    }
    p->key_space = base;
    // The padding key 2^bits - 1 must sort after every real key (< key_space).
    *key_bits = bit_width(base);
  }
};

}  // namespace cdb
