#pragma once
// The cell baselines' shared pieces (baselines/common) on their own: the cell coordinate is
// monotone and clamped at the numerical extremes, a box's cell range holds the cell of
// every point of the box, the home cell of an overlapping pair lies in both boxes' ranges,
// and a scene of one point is one cell. Coordinates, ranges and home cells are computed on
// the executor and must equal the host's bit for bit (no FMA contraction on the device).
// test_bvh_host.cpp runs them on the host executor, test_bvh_cuda.cu on CUDA.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "baselines/common/cell_boxes.h"
#include "baselines/common/cell_coord.h"
#include "baselines/common/cell_range.h"
#include "baselines/common/home_cell.h"
#include "baselines/common/scene_stats.h"
#include "baselines/grid/grid_geometry.h"
#include "baselines/hash/spatial_hash.h"

namespace cdb::test {

inline std::string hex(float x) {
  char text[32];
  std::snprintf(text, sizeof text, "%a", double(x));
  return text;
}

// Ascending floats from -FLT_MAX to FLT_MAX: zeros, subnormals, the normal range's ends,
// cell borders of every lattice below (multiples of 0.1 near 1000.3, of 3e29 near 1e30),
// each with its float neighbours.
inline std::vector<float> extreme_coordinates() {
  const float big = std::numeric_limits<float>::max();
  std::vector<float> base = {0.0f,    0x1p-149f, 0x1p-140f, 0x1p-126f, 1e-30f, 1e-3f, 0.1f,
                             0.25f,   1.0f,      3.0f,      1000.2f,   1000.3f, 1000.4f,
                             1e6f,    3e29f,     1e30f,     1.3e30f,   0x1p60f, 1e38f,
                             3e38f,   big};
  std::vector<float> xs;
  for (float b : base)
    for (float v : {b, -b})
      for (float x : {std::nextafter(v, -big), v, std::nextafter(v, big)}) xs.push_back(x);
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  return xs;
}

// Lattices of both baselines' kinds: power-of-two cells from 2^-126 to 2^130 (the grid's
// range) and other sizes (the hash's), including inverse cells of 0 and FLT_MAX, at
// origins across the whole float range.
inline std::vector<CellLattice<float>> extreme_lattices() {
  const float big = std::numeric_limits<float>::max();
  std::vector<CellLattice<float>> lattices;
  for (float origin : {-big, -3e38f, -1e30f, -1000.3f, -1.0f, 0.0f, 0x1p-140f, 0.25f, 1000.3f,
                       1e30f, 3e38f})
    for (float inv : {0.0f, 0x1p-130f, 0x1p-126f, 0x1p-60f, 1.0f / 3.0f, 1.0f, 10.0f, 1.0f / 3e29f,
                      0x1p60f, 0x1p126f, big})
      lattices.push_back({{origin, origin, origin}, inv});
  return lattices;
}

// Coordinate of x along axis 0 of each lattice: lattice i / num_x, x i % num_x.
struct CellCoordFn {
  const float* x;
  const CellLattice<float>* lattices;
  uint32_t num_x;
  uint32_t* out;
  CDB_HD void operator()(uint32_t i) const {
    const CellLattice<float> g = lattices[i / num_x];
    out[i] = cell_coord(x[i % num_x], g.origin[0], g.inv_cell);
  }
};

template <class Exec>
void check_cell_coord_monotone_at_extremes() {
  const std::vector<float> xs = extreme_coordinates();
  const std::vector<CellLattice<float>> lattices = extreme_lattices();
  const uint32_t nx = uint32_t(xs.size()), n = nx * uint32_t(lattices.size());
  Exec exec;
  Array<float> x(exec.memory(), "test.x");
  Array<CellLattice<float>> g(exec.memory(), "test.lattices");
  Array<uint32_t> out(exec.memory(), "test.coords");
  x.reserve(nx);
  g.reserve(lattices.size());
  out.reserve(n);
  exec.copy_from_host(x.data(), xs.data(), nx);
  exec.copy_from_host(g.data(), lattices.data(), lattices.size());
  exec.for_each_n(n, CellCoordFn{x.data(), g.data(), nx, out.data()});
  std::vector<uint32_t> got(n);
  exec.copy_to_host(got.data(), out.data(), n);
  for (uint32_t l = 0; l < lattices.size(); ++l) {
    const CellLattice<float>& lat = lattices[l];
    const std::string what = "origin " + hex(lat.origin[0]) + " inv_cell " + hex(lat.inv_cell);
    for (uint32_t k = 0; k < nx; ++k) {
      const uint32_t c = got[l * nx + k];
      ASSERT_EQ(c, cell_coord(xs[k], lat.origin[0], lat.inv_cell)) << what << " x " << hex(xs[k]);
      ASSERT_LE(c, kMaxCellCoord) << what;
      if (xs[k] <= lat.origin[0]) {
        ASSERT_EQ(c, 0u) << what << " x " << hex(xs[k]);
      }
      if (k > 0) {
        ASSERT_LE(got[l * nx + k - 1], c) << what << " x " << hex(xs[k - 1]) << ", " << hex(xs[k]);
      }
    }
  }
  // Spot values: the clamp at the top, exact borders of a power-of-two cell, and a lattice
  // whose origin and cell make x - origin overflow (finite scaled first).
  EXPECT_EQ(cell_coord(3e38f, -3e38f, 0x1p-60f), kMaxCellCoord);
  EXPECT_EQ(cell_coord(2.0f, 0.0f, 0.5f), 1u);
  EXPECT_EQ(cell_coord(std::nextafter(2.0f, 0.0f), 0.0f, 0.5f), 0u);
  EXPECT_EQ(cell_coord(3e38f, -3e38f, 0x1p-128f), 1u);
}

// Boxes, points and pairs of one lattice, computed on the executor.
struct BoxCellsFn {
  CellLattice<float> lattice;
  const vec4f* lo;
  const vec4f* hi;
  const vec4f* points;  // one per box, inside it
  CellRange* ranges;
  CellCoords* point_cells;
  CellCoords* homes;  // of boxes i and i + 1
  uint32_t n;
  CDB_HD void operator()(uint32_t i) const {
    ranges[i] = cell_range(lattice, lo[i], hi[i]);
    point_cells[i] = cell_of(lattice, points[i]);
    if (i + 1 < n) homes[i] = home_cell(lattice, lo[i], lo[i + 1]);
  }
};

inline bool in_range(const CellCoords& c, const CellRange& r) {
  return r.lo.x <= c.x && c.x <= r.hi.x && r.lo.y <= c.y && c.y <= r.hi.y && r.lo.z <= c.z &&
         c.z <= r.hi.z;
}

inline bool same_cell(const CellCoords& a, const CellCoords& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

inline bool same_range(const CellRange& a, const CellRange& b) {
  return same_cell(a.lo, b.lo) && same_cell(a.hi, b.hi);
}

// A chain of boxes 1 to 3 edges wide (clamped to the finite floats), in which box i + 1
// overlaps box i: on each axis it starts at box i's far face (touching), at its near face,
// inside it, or one edge before it. With edges on the lattice's cell borders, boxes touch
// exactly on them. One point per box: a corner, one float inside the far face, or a
// random point.
struct BoxChain {
  CellLattice<float> lattice;
  std::vector<vec4f> lo, hi, points;
};

inline BoxChain box_chain(CellLattice<float> lattice, float offset, float edge, uint32_t n,
                          uint32_t seed) {
  const float big = std::numeric_limits<float>::max();
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> widths(1, 3), pick(0, 3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  auto inside = [&](float l, float h) { return std::clamp(l + unit(rng) * (h - l), l, h); };
  BoxChain c{lattice, {}, {}, {}};
  float at[3] = {offset, offset, offset};
  for (uint32_t i = 0; i < n; ++i) {
    vec4f lo{at[0], at[1], at[2], 0.0f}, hi{}, p{};
    const float* l = &lo.x;
    float* h = &hi.x;
    float* pk = &p.x;
    for (int k = 0; k < 3; ++k) h[k] = std::min(l[k] + edge * float(widths(rng)), big);
    for (int k = 0; k < 3; ++k) {
      switch (pick(rng)) {
        case 0: pk[k] = l[k]; break;
        case 1: pk[k] = h[k]; break;
        case 2: pk[k] = std::max(l[k], std::nextafter(h[k], l[k])); break;
        default: pk[k] = inside(l[k], h[k]); break;
      }
      switch (pick(rng)) {
        case 0: at[k] = h[k]; break;
        case 1: at[k] = l[k]; break;
        case 2: at[k] = inside(l[k], h[k]); break;
        default: at[k] = std::max(l[k] - edge, -big); break;
      }
    }
    c.lo.push_back(lo);
    c.hi.push_back(hi);
    c.points.push_back(p);
  }
  return c;
}

template <class Exec>
void check_box_ranges_hold_their_points_and_homes() {
  const float big = std::numeric_limits<float>::max();
  const std::vector<BoxChain> chains = {
      // Unit cells, boxes on their borders; subnormal edges on the grid's finest cell
      // (2^-126) and on the hash's FLT_MAX inverse; rounded offsets; 1e30 and edges from
      // -3e38 up to FLT_MAX, where x - origin overflows; cells of 1/3.
      box_chain({{0.0f, 0.0f, 0.0f}, 1.0f}, 0.0f, 1.0f, 600, 1),
      box_chain({{0.0f, 0.0f, 0.0f}, 0x1p126f}, 0.0f, 0x1p-130f, 600, 2),
      box_chain({{0.0f, 0.0f, 0.0f}, big}, 0x1p-140f, 0x1p-135f, 600, 3),
      box_chain({{1000.3f, 1000.3f, 1000.3f}, 10.0f}, 1000.3f, 0.1f, 600, 4),
      box_chain({{1e30f, 1e30f, 1e30f}, 1.0f / 3e29f}, 1e30f, 3e29f, 600, 5),
      box_chain({{-3e38f, -3e38f, -3e38f}, 0x1p-124f}, -3e38f, 3e37f, 600, 6),
      box_chain({{0.25f, 0.25f, 0.25f}, 3.0f}, 0.25f, 1.0f / 3.0f, 600, 7),
  };
  for (size_t ci = 0; ci < chains.size(); ++ci) {
    const BoxChain& c = chains[ci];
    const uint32_t n = uint32_t(c.lo.size());
    Exec exec;
    Array<vec4f> lo(exec.memory(), "test.lo"), hi(exec.memory(), "test.hi"),
        points(exec.memory(), "test.points");
    Array<CellRange> ranges(exec.memory(), "test.ranges");
    Array<CellCoords> point_cells(exec.memory(), "test.point_cells"),
        homes(exec.memory(), "test.homes");
    for (auto* a : {&lo, &hi, &points}) a->reserve(n);
    ranges.reserve(n);
    point_cells.reserve(n);
    homes.reserve(n);
    exec.copy_from_host(lo.data(), c.lo.data(), n);
    exec.copy_from_host(hi.data(), c.hi.data(), n);
    exec.copy_from_host(points.data(), c.points.data(), n);
    exec.for_each_n(n, BoxCellsFn{c.lattice, lo.data(), hi.data(), points.data(), ranges.data(),
                                  point_cells.data(), homes.data(), n});
    std::vector<CellRange> r(n);
    std::vector<CellCoords> pc(n), home(n);
    exec.copy_to_host(r.data(), ranges.data(), n);
    exec.copy_to_host(pc.data(), point_cells.data(), n);
    exec.copy_to_host(home.data(), homes.data(), n);
    uint64_t multi_cell = 0;
    for (uint32_t i = 0; i < n; ++i) {
      const std::string what = "chain " + std::to_string(ci) + " box " + std::to_string(i);
      ASSERT_TRUE(same_range(r[i], cell_range(c.lattice, c.lo[i], c.hi[i]))) << what;
      ASSERT_TRUE(same_cell(pc[i], cell_of(c.lattice, c.points[i]))) << what;
      ASSERT_TRUE(in_range(pc[i], r[i])) << what;
      multi_cell += r[i].cells() > 1;
      if (i + 1 == n) continue;
      ASSERT_TRUE(overlaps(c.lo[i], c.hi[i], c.lo[i + 1], c.hi[i + 1])) << what;
      ASSERT_TRUE(same_cell(home[i], home_cell(c.lattice, c.lo[i], c.lo[i + 1]))) << what;
      ASSERT_TRUE(in_range(home[i], r[i]) && in_range(home[i], r[i + 1])) << what;
    }
    // The chain must cross cell borders, or it tests nothing about them.
    EXPECT_GT(multi_cell, 0u) << "chain " << ci;
  }
}

// Every vertex at one point: the scene statistics reduce to that point and width 0, and
// both baselines' lattices put every box, and every pair's home, in cell 0.
template <class Exec>
void check_one_point_scene_is_one_cell() {
  for (float p : {0.25f, -0.25f, 0x1p-140f, 1e30f, -3e38f, 3e38f}) {
    const std::string what = "point " + hex(p);
    const uint32_t n = 1000;
    Exec exec;
    CellBoxes<Exec> boxes(exec, "test");
    boxes.reserve_boxes(n);
    boxes.temp.reserve(std::max(boxes.box_temp_bytes(exec, n),
                                exec.template reduce_temp_bytes_of<TrimmedWidths>(n)));
    Array<CellLattice<float>> lattice(exec.memory(), "test.lattice");
    Array<GridLayout> layout(exec.memory(), "test.layout");
    Array<TrimmedWidths> trimmed(exec.memory(), "test.trimmed");
    Array<unsigned long long> key_bits(exec.memory(), "test.key_bits");
    lattice.reserve(1);
    layout.reserve(1);
    trimmed.reserve(1);
    key_bits.reserve(1);
    const vec4f at{p, p, p, 0.0f};
    exec.fill(boxes.lo.data(), n, at);
    exec.fill(boxes.hi.data(), n, at);
    reduce_scene_stats(exec, boxes, n);
    exec.for_each_n(1, HashLatticeFn{boxes.scene.data(), n, 1.0, lattice.data()});
    exec.reduce(n, TrimmedWidthsFn{boxes.lo.data(), boxes.hi.data(), boxes.scene.data(), n},
                TrimmedWidthsOp{}, TrimmedWidths{0.0, 0ull}, trimmed.data(), boxes.temp.data(),
                boxes.temp.size());
    exec.for_each_n(1, GridLayoutFn{boxes.scene.data(), trimmed.data(), layout.data(),
                                    key_bits.data()});
    SceneStats s{};
    CellLattice<float> hash{};
    GridLayout grid{};
    exec.copy_to_host(&s, boxes.scene.data(), 1);
    exec.copy_to_host(&hash, lattice.data(), 1);
    exec.copy_to_host(&grid, layout.data(), 1);
    EXPECT_EQ(s.width_sum, 0.0) << what;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(s.lo[k], p) << what;
      EXPECT_EQ(s.hi[k], p) << what;
    }
    EXPECT_EQ(scene_extent(s), 0.0) << what;
    EXPECT_EQ(grid.levels, 1u) << what;
    for (int k = 0; k < 3; ++k) EXPECT_EQ(grid.level[0].dims[k], 1u) << what;
    for (const CellLattice<float>& g : {hash, level_lattice(grid, 0)}) {
      const CellRange r = cell_range(g, at, at);
      EXPECT_EQ(r.cells(), 1u) << what;
      EXPECT_TRUE(same_cell(r.lo, CellCoords{0, 0, 0})) << what;
      EXPECT_TRUE(same_cell(home_cell(g, at, at), CellCoords{0, 0, 0})) << what;
    }
  }
}

// The scene statistics on the executor against a serial pass: bounds bit for bit, the
// width sum to rounding (the reduction adds in another order), at unit, tiny and 1e38
// scales.
template <class Exec>
void check_scene_stats_reduction() {
  for (float scale : {1.0f, 1e-30f, 1e38f}) {
    const uint32_t n = 5000;
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coord(-1.0f, 1.0f), size(0.0f, 0.01f);
    std::vector<vec4f> lo(n), hi(n);
    SceneStats want = SceneStatsOp::identity();
    for (uint32_t i = 0; i < n; ++i) {
      lo[i] = {coord(rng) * scale, coord(rng) * scale, coord(rng) * scale, 0.0f};
      hi[i] = {lo[i].x + size(rng) * scale, lo[i].y + size(rng) * scale,
               lo[i].z + size(rng) * scale, 0.0f};
      want = SceneStatsOp{}(want, SceneStatsFn{lo.data(), hi.data()}(i));
    }
    Exec exec;
    CellBoxes<Exec> boxes(exec, "test");
    boxes.reserve_boxes(n);
    boxes.temp.reserve(boxes.box_temp_bytes(exec, n));
    exec.copy_from_host(boxes.lo.data(), lo.data(), n);
    exec.copy_from_host(boxes.hi.data(), hi.data(), n);
    reduce_scene_stats(exec, boxes, n);
    SceneStats got{};
    exec.copy_to_host(&got, boxes.scene.data(), 1);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(got.lo[k], want.lo[k]) << scale;
      EXPECT_EQ(got.hi[k], want.hi[k]) << scale;
    }
    EXPECT_GT(want.width_sum, 0.0) << scale;
    EXPECT_NEAR(got.width_sum, want.width_sum, 1e-12 * want.width_sum) << scale;
  }
}

}  // namespace cdb::test
