#pragma once
// Box precision (docs/design.md "Speed/accuracy knobs"): q16 boxes and the outward-rounded
// margin on the numerical extremes, written once over the executor; test_knobs_host.cpp
// runs them on the host executor, test_bvh_cuda.cu on CUDA.
// - every q16 box contains its exact box and lies within one grid cell of it per side;
// - the float boxes (margin, q16) contain the boxes computed in double from the same
//   vertices with the margin added in double (fp64 differs only in how the vertices are
//   rounded: offset_cases.h);
// - the executor's grid (DeviceMesh) equals the one computed here from the vertices;
// - every pipeline reports exactly the O(N^2) overlaps of the same q16 boxes, a superset
//   of the exact pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "baseline_cases.h"
#include "knob_cases.h"
#include "cdbench/pipeline/device_mesh.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

// `s` plus a point triangle at (p, p, p) on every frame: the scene's bounds, and so the q16
// grid, reach out to p.
inline SceneFrames with_point_at(SceneFrames s, float p) {
  const uint32_t v = s.topology.num_vertices++;
  s.topology.faces.push_back({v, v, v});
  for (auto& frame : s.frames) frame.push_back({p, p, p});
  return s;
}

// Coordinates near 1e+30 and 1e-30, subnormals, a 1e6-wide scene with 1e-3 features, all
// triangles at one point, degenerate and duplicate triangles, exactly touching boxes (the
// cube lattices), giants, one triangle, no triangle: extreme_cases() and what it lacks.
inline std::vector<BaselineCase> precision_cases() {
  std::vector<BaselineCase> cases = extreme_cases();
  const auto soup = [](uint64_t n, double scale, double duplicates) {
    return frames_of(*make_generator(
        "soup", {{"triangles", n}, {"scale", scale}, {"duplicates", duplicates}, {"frames", 2}, {"seed", 7}}));
  };
  cases.push_back({"soup_1e30", [=] { return soup(500, 1e30, 0.0); }});
  cases.push_back({"soup_1em30", [=] { return soup(500, 1e-30, 0.0); }});
  cases.push_back({"soup_dups", [=] { return soup(500, 1.0, 0.5); }});
  cases.push_back({"cubes_offset_1e30", [] { return offset_cube_lattice(3, 3e29f, 1e30f); }});
  // The lattice of 1e-3 cubes in a scene 1e6 wide: q16 cells of 15 units, every cube in one.
  cases.push_back({"span_1e6_cubes_1em3", [] { return with_point_at(cube_lattice(3, 1e-3f), 1e6f); }});
  cases.push_back({"one_triangle", [=] { return soup(1, 1.0, 0.0); }});
  cases.push_back({"empty", [=] { return soup(0, 1.0, 0.0); }});
  return cases;
}

// The grid of a frame from its vertices (and the previous frame's), bounds by plain min/max
// here rather than the executor's reduction.
inline BoxGrid host_box_grid(const std::vector<vec3f>& v, const std::vector<vec3f>* prev) {
  Aabb<float> b = Aabb<float>::empty();
  for (const vec3f& p : v) b.grow(vec4f{p.x, p.y, p.z, 0.0f});
  if (prev)
    for (const vec3f& p : *prev) b.grow(vec4f{p.x, p.y, p.z, 0.0f});
  return box_grid(b);
}

struct Boxes {
  std::vector<vec4f> lo, hi;
};

// face_box on the host with these knobs; q16 over host_box_grid.
inline Boxes knob_boxes(const Topology& topo, const std::vector<vec3f>& v, const std::vector<vec3f>* prev,
                        float margin, BoxPrecision precision) {
  const BoxGrid grid = host_box_grid(v, prev);
  const MeshView m{v.data(), topo.faces.data(), uint32_t(topo.faces.size()), prev ? prev->data() : nullptr, margin,
                   precision == BoxPrecision::q16 ? &grid : nullptr};
  Boxes b;
  b.lo.resize(topo.faces.size());
  b.hi.resize(topo.faces.size());
  for (uint32_t f = 0; f < m.num_faces; ++f) face_box(m, f, b.lo[f], b.hi[f]);
  return b;
}

inline float axis_of(const vec4f& v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }
inline const BoxGridAxis& axis_of(const BoxGrid& g, int k) { return k == 0 ? g.x : k == 1 ? g.y : g.z; }

// Each q16 box contains its exact box and is less than one cell larger on each side: its
// bound lies above the exact bound minus one cell, or is the first float below that (the
// line rounded outward to float), a thousandth of a cell allowed for the double-rounded
// lines. An axis without extent is not snapped.
inline void check_q16_boxes(const SceneFrames& s) {
  const Topology& topo = s.topology;
  for (size_t f = 0; f < s.frames.size(); ++f) {
    const std::vector<vec3f>& v = s.frames[f];
    const BoxGrid grid = host_box_grid(v, nullptr);
    const Boxes q = knob_boxes(topo, v, nullptr, 0.0f, BoxPrecision::q16);
    for (size_t t = 0; t < topo.faces.size(); ++t) {
      vec4f lo, hi;
      reference_box(topo.faces[t], v, nullptr, 0.0f, lo, hi);
      for (int k = 0; k < 3; ++k) {
        const float ql = axis_of(q.lo[t], k), qh = axis_of(q.hi[t], k), el = axis_of(lo, k), eh = axis_of(hi, k);
        const double cell = axis_of(grid, k).cell;
        ASSERT_LE(ql, el) << "frame " << f << " face " << t << " axis " << k;
        ASSERT_GE(qh, eh) << "frame " << f << " face " << t << " axis " << k;
        const double reach = cell * (1.0 + 0x1p-10);
        ASSERT_GT(double(std::nextafter(ql, INFINITY)), double(el) - reach)
            << "frame " << f << " face " << t << " axis " << k << ": lo " << el << " snapped to " << ql
            << ", cell " << cell;
        ASSERT_LT(double(std::nextafter(qh, -INFINITY)), double(eh) + reach)
            << "frame " << f << " face " << t << " axis " << k << ": hi " << eh << " snapped to " << qh
            << ", cell " << cell;
        if (cell == 0.0) {
          ASSERT_EQ(ql, el);
          ASSERT_EQ(qh, eh);
        }
      }
    }
  }
}

// The boxes face_box makes with `margin` and `precision` contain the boxes computed in
// double from the same vertices, the margin subtracted and added in double.
inline void check_contains_double_boxes(const SceneFrames& s, float margin, BoxPrecision precision) {
  const Topology& topo = s.topology;
  for (size_t f = 0; f < s.frames.size(); ++f) {
    const std::vector<vec3f>& v = s.frames[f];
    const Boxes b = knob_boxes(topo, v, nullptr, margin, precision);
    for (size_t t = 0; t < topo.faces.size(); ++t) {
      const Tri& tri = topo.faces[t];
      for (int k = 0; k < 3; ++k) {
        const auto coord = [&](uint32_t i) {
          return double(k == 0 ? v[i].x : k == 1 ? v[i].y : v[i].z);
        };
        const double lo = std::min({coord(tri.v0), coord(tri.v1), coord(tri.v2)}) - double(margin);
        const double hi = std::max({coord(tri.v0), coord(tri.v1), coord(tri.v2)}) + double(margin);
        ASSERT_LE(double(axis_of(b.lo[t], k)), lo) << "frame " << f << " face " << t << " axis " << k
                                                   << " margin " << margin << " " << box_precision_name(precision);
        ASSERT_GE(double(axis_of(b.hi[t], k)), hi) << "frame " << f << " face " << t << " axis " << k
                                                   << " margin " << margin << " " << box_precision_name(precision);
      }
    }
  }
}

// Margins for the double check: none, one far below the float spacing of the scene's
// largest coordinate (2^-30 of it; to nearest, lo - M would stay lo), and 1% of its extent.
inline std::vector<float> precision_margins(const SceneFrames& s) {
  float largest = 0.0f, lo = INFINITY, hi = -INFINITY;
  for (const auto& v : s.frames)
    for (const vec3f& p : v)
      for (float c : {p.x, p.y, p.z}) {
        largest = std::max(largest, std::fabs(c));
        lo = std::min(lo, c);
        hi = std::max(hi, c);
      }
  const float below_spacing = std::max(std::ldexp(largest, -30), 0x1p-149f);
  const float extent = hi > lo ? float(std::min(0.01 * (double(hi) - double(lo)), 1e36)) : 1.0f;
  return {0.0f, below_spacing, extent};
}

// The executor's grid (DeviceMesh::update_grid: a reduction on the executor and one
// thread) equals host_box_grid, bit for bit, on every frame, with and without swept boxes.
template <class Exec>
void check_executor_grid(const SceneFrames& s, bool swept) {
  Exec exec;
  DeviceMesh<Exec> mesh(exec);
  PipelineConfig cfg;
  cfg.boxes.precision = BoxPrecision::q16;
  cfg.boxes.swept = swept;
  mesh.set_box_knobs(cfg);
  mesh.set_topology(exec, s.topology, SplitRule::queries);
  for (size_t f = 0; f < s.frames.size(); ++f) {
    mesh.upload(exec, s.frames[f]);
    mesh.update_grid(exec);
    const MeshView m = mesh.view();
    ASSERT_NE(m.grid, nullptr);
    BoxGrid got;
    exec.copy_to_host(&got, m.grid, 1);
    const BoxGrid want = host_box_grid(s.frames[f], swept && f > 0 ? &s.frames[f - 1] : nullptr);
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(axis_of(got, k).origin, axis_of(want, k).origin) << "frame " << f << " axis " << k;
      EXPECT_EQ(axis_of(got, k).cell, axis_of(want, k).cell) << "frame " << f << " axis " << k;
      EXPECT_EQ(axis_of(got, k).inv_cell, axis_of(want, k).inv_cell) << "frame " << f << " axis " << k;
    }
  }
}

// Every pipeline with q16 boxes (and the other box knobs given): exactly the O(N^2)
// overlaps of the q16 boxes computed here, and every exact pair (recall 1). Adds the pairs
// beyond the exact ones, over pipelines and frames, to `extra`.
inline void check_q16_pipelines(const std::string& device, const SceneFrames& s, size_t& extra,
                                float margin = 0.0f, bool swept = false) {
  const Topology& topo = s.topology;
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = growing_config(device, name);
    cfg.boxes.margin = margin;
    cfg.boxes.swept = swept;
    cfg.boxes.precision = BoxPrecision::q16;
    auto p = make_pipeline(cfg);
    p->set_topology(topo);
    for (size_t f = 0; f < s.frames.size(); ++f) {
      const std::vector<vec3f>& v = s.frames[f];
      const std::vector<vec3f>* prev = swept && f > 0 ? &s.frames[f - 1] : nullptr;
      const Boxes b = knob_boxes(topo, v, prev, margin, BoxPrecision::q16);
      std::vector<PrimPair> expected = brute_pairs(b.lo, b.hi);
      if (topo.queries.declared) {
        const PairFilterTables t = pair_filter_tables(topo.objects, topo.queries, topo.faces.size());
        std::erase_if(expected,
                      [&](PrimPair q) { return !pair_wanted(t.face_object.data(), t.partners.data(), q.a, q.b); });
      }
      const auto exact = sweep_oracle_pairs(topo, v, false);
      const FrameStats st = p->run_frame(v);
      const auto got = p->sorted_pairs();
      ASSERT_TRUE(contains_all(got, exact)) << name << " frame " << f << " misses exact pairs";
      const PairSetDiff d = diff_pair_sets(expected, got);
      ASSERT_TRUE(d.equal()) << name << " frame " << f << " (" << st.op << "): " << d.missing_count << " missing, "
                             << d.unexpected_count << " unexpected against the q16 boxes";
      extra += got.size() - exact.size();
    }
  }
}

}  // namespace cdb::test
