#pragma once
// Property tests of the sweep, hash and grid baselines, written once over the executor: on
// nasty soups and on boxes touching exactly along grid-cell boundaries, each must report
// exactly the sweep oracle's pairs on every frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/pair_set.h"
#include "scenes/generators/generators.h"
#include "baselines/grid/uniform_grid.h"
#include "baselines/hash/spatial_hash.h"
#include "cdbench/pipeline/pipeline.h"
#include "baselines/sweep/sweep.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

struct SceneFrames {
  Topology topology;
  std::vector<std::vector<vec3f>> frames;
};

inline SceneFrames frames_of(const FrameSource& source) {
  SceneFrames s{source.topology(), {}};
  s.frames.resize(source.num_frames());
  for (uint32_t f = 0; f < source.num_frames(); ++f) source.frame(f, s.frames[f]);
  return s;
}

// The twelve triangles of a cube's faces, corners given.
inline void add_cube(SceneFrames& s, std::vector<vec3f>& v, vec3f lo, vec3f hi) {
  const uint32_t base = uint32_t(v.size());
  for (int c = 0; c < 8; ++c)
    v.push_back({c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z});
  // Corner c has bit 0 = x, bit 1 = y, bit 2 = z; each face is two triangles.
  const uint32_t quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
  for (const auto& q : quads) {
    s.topology.faces.push_back({base + q[0], base + q[1], base + q[2]});
    s.topology.faces.push_back({base + q[0], base + q[2], base + q[3]});
  }
}

// g^3 cubes of edge `edge` on a lattice of the same spacing, corners at integer multiples:
// neighbours touch exactly on faces, edges and corners, on the very planes a grid of
// cell size `edge` puts its boundaries. Frame 1 halves everything (still exact in binary),
// frame 2 shifts it by 1024 edges.
inline SceneFrames cube_lattice(uint32_t g, float edge) {
  SceneFrames s;
  s.frames.resize(3);
  for (uint32_t f = 0; f < 3; ++f) {
    const float scale = f == 1 ? 0.5f * edge : edge;
    const float shift = f == 2 ? 1024.0f * edge : 0.0f;
    std::vector<vec3f>& v = s.frames[f];
    s.topology.faces.clear();
    for (uint32_t k = 0; k < g; ++k)
      for (uint32_t j = 0; j < g; ++j)
        for (uint32_t i = 0; i < g; ++i)
          add_cube(s, v, {i * scale + shift, j * scale + shift, k * scale + shift},
                   {(i + 1) * scale + shift, (j + 1) * scale + shift, (k + 1) * scale + shift});
  }
  s.topology.num_vertices = uint32_t(s.frames[0].size());
  return s;
}

// A small uniform soup plus `giants` triangles spanning the whole scene (or, with
// `far` set, reaching out to +-3e38): boxes the grid cannot register cheaply.
inline SceneFrames soup_with_giants(uint64_t small, uint32_t giants, bool far) {
  auto soup = make_generator("soup", {{"triangles", small}, {"frames", 2}, {"seed", 5}});
  SceneFrames s = frames_of(*soup);
  for (uint32_t g = 0; g < giants; ++g) {
    const uint32_t base = s.topology.num_vertices + 3 * g;
    s.topology.faces.push_back({base, base + 1, base + 2});
  }
  s.topology.num_vertices += 3 * giants;
  for (auto& v : s.frames)
    for (uint32_t g = 0; g < giants; ++g) {
      const float t = float(g) / float(std::max(giants, 1u));
      const float r = far ? 3e38f : 1.0f;
      v.push_back({-r, t - 0.5f, -r * t});
      v.push_back({r, 0.5f - t, 0.25f});
      v.push_back({0.5f * t, r, r});
    }
  return s;
}

// The cube lattice of cube_lattice(), but at coordinates offset + i * edge computed in
// float: cubes still touch exactly (a shared corner is the same float), while neither the
// lattice planes nor the grid's origin are round numbers, so every subtraction rounds.
inline SceneFrames offset_cube_lattice(uint32_t g, float edge, float offset) {
  SceneFrames s;
  s.frames.resize(2);
  for (uint32_t f = 0; f < 2; ++f) {
    const float e = f == 0 ? edge : 3.0f * edge;
    std::vector<vec3f>& v = s.frames[f];
    s.topology.faces.clear();
    for (uint32_t k = 0; k < g; ++k)
      for (uint32_t j = 0; j < g; ++j)
        for (uint32_t i = 0; i < g; ++i)
          add_cube(s, v, {offset + float(i) * e, offset + float(j) * e, offset + float(k) * e},
                   {offset + float(i + 1) * e, offset + float(j + 1) * e,
                    offset + float(k + 1) * e});
  }
  s.topology.num_vertices = uint32_t(s.frames[0].size());
  return s;
}

// n triangles with every vertex at one point (frame 0 at p, frame 1 at -p): zero-width
// boxes, a zero-extent scene, all pairs overlapping.
inline SceneFrames all_at_one_point(uint32_t n, float p) {
  SceneFrames s;
  s.frames.resize(2);
  for (uint32_t t = 0; t < n; ++t) s.topology.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
  s.topology.num_vertices = 3 * n;
  s.frames[0].assign(3 * n, {p, p, p});
  s.frames[1].assign(3 * n, {-p, -p, -p});
  return s;
}

// Triangles whose widths spread log-uniformly over 2^-12..1 in a unit cube: boxes on many
// grid levels, pairs across levels.
inline SceneFrames multiscale_soup(uint32_t n, uint32_t seed) {
  SceneFrames s;
  s.frames.resize(2);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), exponent(-12.0f, 0.0f);
  for (uint32_t t = 0; t < n; ++t) {
    s.topology.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    const float size = std::exp2(exponent(rng));
    const vec3f c{unit(rng), unit(rng), unit(rng)};
    for (int k = 0; k < 3; ++k) {
      const vec3f d{size * (unit(rng) - 0.5f), size * (unit(rng) - 0.5f),
                    size * (unit(rng) - 0.5f)};
      s.frames[0].push_back({c.x + d.x, c.y + d.y, c.z + d.z});
      s.frames[1].push_back({c.x + 0.5f * d.y, c.y + 0.5f * d.z, c.z + 0.5f * d.x});
    }
  }
  s.topology.num_vertices = 3 * n;
  return s;
}

// g^3 pairs of coincident triangles of width 0.2, one per unit lattice point, plus a point
// triangle pinning the grid's origin at 0 (cell 0.25). Frame 0: each box inside one cell.
// Frames 1 and 2: shifted by 0.15, each box straddles a cell corner (8 cells), eight times
// the entries frame 0 planned for.
inline SceneFrames straddling_pairs(uint32_t g) {
  SceneFrames s;
  s.frames.resize(3);
  s.topology.faces.push_back({0, 0, 0});
  for (auto& v : s.frames) v.push_back({0.0f, 0.0f, 0.0f});
  for (uint32_t k = 0; k < g; ++k)
    for (uint32_t j = 0; j < g; ++j)
      for (uint32_t i = 0; i < g; ++i) {
        const uint32_t base = uint32_t(s.frames[0].size());
        s.topology.faces.push_back({base, base + 1, base + 2});
        s.topology.faces.push_back({base, base + 1, base + 2});
        for (uint32_t f = 0; f < 3; ++f) {
          const float d = f == 0 ? 0.02f : 0.15f, w = 0.2f;
          const vec3f o{float(i) + d, float(j) + d, float(k) + d};
          s.frames[f].push_back(o);
          s.frames[f].push_back({o.x + w, o.y, o.z + w});
          s.frames[f].push_back({o.x, o.y + w, o.z + 0.5f * w});
        }
      }
  s.topology.num_vertices = uint32_t(s.frames[0].size());
  return s;
}

// n boxes at float's limit, each a triangle (min, max, max) as a box stream makes them:
// on each axis a box lies near +FLT_MAX, near -FLT_MAX, around 0 or across the whole range,
// up to 4e37 wide, a third of those at an end reaching it exactly (FLT_MAX - lo overflows
// float there); boxes of one region overlap often. Frame 1 mirrors frame 0 through 0. With
// a margin (check_baselines), the boxes at the ends overflow to +-inf.
inline SceneFrames float_limit_boxes(uint32_t n, uint32_t seed) {
  const float big = std::numeric_limits<float>::max();
  SceneFrames s;
  s.frames.resize(2);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> region(0, 3), third(0, 2);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (uint32_t b = 0; b < n; ++b) {
    float lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      const float w = 1e36f + 3.9e37f * unit(rng);
      switch (region(rng)) {
        case 0:
          lo[k] = big - 4e37f * unit(rng);
          hi[k] = third(rng) == 0 ? big : std::min(lo[k] + w, big);
          break;
        case 1:
          hi[k] = -big + 4e37f * unit(rng);
          lo[k] = third(rng) == 0 ? -big : std::max(hi[k] - w, -big);
          break;
        case 2:
          lo[k] = -2e37f * unit(rng);
          hi[k] = lo[k] + w;
          break;
        default:
          lo[k] = -big;
          hi[k] = big;
          break;
      }
    }
    s.topology.faces.push_back({2 * b, 2 * b + 1, 2 * b + 1});
    s.frames[0].push_back({lo[0], lo[1], lo[2]});
    s.frames[0].push_back({hi[0], hi[1], hi[2]});
    s.frames[1].push_back({-hi[0], -hi[1], -hi[2]});
    s.frames[1].push_back({-lo[0], -lo[1], -lo[2]});
  }
  s.topology.num_vertices = 2 * n;
  return s;
}

// The grid pipeline through the factory on every frame of `scene`: exact against the
// oracle; returns each frame's op.
inline std::vector<std::string> grid_pipeline_ops(const std::string& device,
                                                  const SceneFrames& scene) {
  PipelineConfig cfg;
  cfg.name = "grid";
  cfg.device = device;
  auto p = make_pipeline(cfg);
  p->set_topology(scene.topology);
  std::vector<std::string> ops;
  for (const auto& v : scene.frames) {
    const FrameStats s = p->run_frame(v);
    const std::vector<PrimPair> expected = sweep_oracle_pairs(scene.topology, v);
    EXPECT_EQ(s.pairs, expected.size()) << ops.size();
    EXPECT_TRUE(diff_pair_sets(expected, p->sorted_pairs()).equal()) << ops.size();
    EXPECT_EQ(s.timing.query_reruns > 0, s.op == "regrid") << ops.size();
    ops.push_back(s.op);
  }
  return ops;
}

// A SceneFrames as a frame source, for the pipeline factory.
class StoredFrames final : public FrameSource {
 public:
  explicit StoredFrames(SceneFrames s) : s_(std::move(s)) {}
  const Topology& topology() const override { return s_.topology; }
  uint32_t num_frames() const override { return uint32_t(s_.frames.size()); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override { widen_to_double(s_.frames.at(k), out); }
  std::string describe() const override { return "stored test frames"; }

 private:
  SceneFrames s_;
};

// Degenerate triangles: zero-area (a repeated corner), collinear corners, and exact
// duplicates of both, scattered over a small lattice so they overlap each other and
// regular triangles; frame 1 moves every other one.
inline SceneFrames degenerate_triangles(uint32_t n) {
  SceneFrames s;
  s.frames.resize(2);
  for (uint32_t t = 0; t < n; ++t) {
    const float x = float(t % 10) * 0.3f, y = float((t / 10) % 10) * 0.3f, z = float(t / 100) * 0.3f;
    std::vector<vec3f> corners;
    switch (t % 4) {
      case 0: corners = {{x, y, z}, {x, y, z}, {x + 0.5f, y, z}}; break;          // repeated corner
      case 1: corners = {{x, y, z}, {x + 0.25f, y, z}, {x + 0.5f, y, z}}; break;  // collinear
      case 2: corners = {{x, y, z}, {x, y, z}, {x, y, z}}; break;                 // a point
      default: corners = {{x, y, z}, {x + 0.5f, y, z}, {x, y + 0.5f, z}}; break;  // regular
    }
    for (uint32_t f = 0; f < 2; ++f)
      for (const vec3f& c : corners)
        s.frames[f].push_back(f == 1 && t % 2 ? vec3f{c.x + 0.1f, c.y, c.z} : c);
    s.topology.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    if (t % 5 == 0) s.topology.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});  // duplicate face
  }
  s.topology.num_vertices = 3 * n;
  return s;
}

struct BaselineCase {
  std::string name;
  std::function<SceneFrames()> make;
};

inline void PrintTo(const BaselineCase& c, std::ostream* os) { *os << c.name; }

inline std::string baseline_case_name(const testing::TestParamInfo<BaselineCase>& info) {
  return info.param.name;
}

// The numerical extremes of the accuracy issue, for every pipeline: touching boxes at unit,
// subnormal (2^-140) and huge scales, a 1e6-wide scene with 1e-3 features, all triangles at
// one point, giant and multiscale boxes, coordinates near 1e38, degenerate triangles.
inline std::vector<BaselineCase> extreme_cases() {
  return {
      {"cubes_unit_4", [] { return cube_lattice(4, 1.0f); }},
      {"cubes_subnormal_3", [] { return cube_lattice(3, 0x1p-140f); }},
      {"cubes_huge_3", [] { return cube_lattice(3, 0x1p60f); }},
      {"wide_1e6_features_1em3", [] { return offset_cube_lattice(4, 1e-3f, 1e6f); }},
      {"one_point_200", [] { return all_at_one_point(200, 0.25f); }},
      {"one_point_1e30_100", [] { return all_at_one_point(100, 1e30f); }},
      {"giants_10", [] { return soup_with_giants(1000, 10, false); }},
      {"multiscale_2000", [] { return multiscale_soup(2000, 5); }},
      {"soup_1e38", [] {
         return frames_of(*make_generator("soup", {{"triangles", 500}, {"scale", 1e38}, {"frames", 2}}));
       }},
      {"degenerate_400", [] { return degenerate_triangles(400); }},
      {"float_limit_200", [] { return float_limit_boxes(200, 1); }},
  };
}

inline std::vector<BaselineCase> baseline_cases() {
  std::vector<BaselineCase> cases;
  for (uint64_t n : {0ull, 1ull, 2ull, 7ull, 1000ull, 20000ull})
    for (const char* dist : {"uniform", "clustered", "identical"})
      for (double scale : {1.0, 1e-20, 1e20}) {
        if (std::string(dist) == "identical" && n > 2000) continue;
        std::string name = "soup_n" + std::to_string(n) + "_" + dist;
        name += scale == 1.0 ? "_unit" : scale < 1.0 ? "_tiny" : "_huge";
        cases.push_back({name, [=] {
                           return frames_of(*make_generator(
                               "soup", {{"triangles", n},
                                        {"distribution", dist},
                                        {"scale", scale},
                                        {"frames", 3},
                                        {"seed", 17 + n}}));
                         }});
      }
  cases.push_back({"soup_n1000_uniform_dups", [] {
                     return frames_of(*make_generator(
                         "soup", {{"triangles", 1000}, {"duplicates", 0.5}, {"frames", 3}}));
                   }});
  cases.push_back({"soup_n20000_clustered_dups", [] {
                     return frames_of(*make_generator("soup", {{"triangles", 20000},
                                                               {"distribution", "clustered"},
                                                               {"duplicates", 0.3},
                                                               {"frames", 2}}));
                   }});
  cases.push_back({"soup_n1000_uniform_1e38", [] {
                     return frames_of(*make_generator(
                         "soup", {{"triangles", 1000}, {"scale", 1e38}, {"frames", 2}}));
                   }});
  cases.push_back({"float_limit_300", [] { return float_limit_boxes(300, 3); }});
  cases.push_back({"cubes_unit_8", [] { return cube_lattice(8, 1.0f); }});
  cases.push_back({"cubes_tiny_5", [] { return cube_lattice(5, 0x1p-70f); }});
  cases.push_back({"cubes_huge_5", [] { return cube_lattice(5, 0x1p60f); }});
  cases.push_back({"giants_10", [] { return soup_with_giants(3000, 10, false); }});
  cases.push_back({"giants_100", [] { return soup_with_giants(3000, 100, false); }});
  cases.push_back({"giants_far_5", [] { return soup_with_giants(1000, 5, true); }});
  cases.push_back({"giants_far_60", [] { return soup_with_giants(1000, 60, true); }});
  cases.push_back({"giant_1", [] { return soup_with_giants(3000, 1, false); }});
  cases.push_back({"giant_far_1", [] { return soup_with_giants(3000, 1, true); }});
  cases.push_back({"cubes_offset_6", [] { return offset_cube_lattice(6, 0.1f, 1000.3f); }});
  cases.push_back({"cubes_offset_huge_4", [] { return offset_cube_lattice(4, 3e29f, 1e30f); }});
  cases.push_back({"one_point_300", [] { return all_at_one_point(300, 0.25f); }});
  cases.push_back({"one_point_1e30_200", [] { return all_at_one_point(200, 1e30f); }});
  cases.push_back({"multiscale_5000", [] { return multiscale_soup(5000, 3); }});
  return cases;
}

// Downloads, sorts and compares one query's pairs with the oracle.
template <class Exec>
void expect_pairs(Exec& exec, const std::vector<PrimPair>& expected, const Array<PrimPair>& pairs,
                  const Array<unsigned long long>& count, const std::string& what) {
  unsigned long long found = 0;
  exec.copy_to_host(&found, count.data(), 1);
  ASSERT_EQ(found, expected.size()) << what;
  std::vector<PrimPair> got(found);
  exec.copy_to_host(got.data(), pairs.data(), found);
  sort_by_pair_key(got);
  const PairSetDiff d = diff_pair_sets(expected, got);
  ASSERT_TRUE(d.equal()) << what << ": " << d.missing_count << " missing, "
                         << d.unexpected_count << " unexpected";
}

// How often the hash coarsened its grid and the grid re-ran a frame to a larger plan.
struct BaselineReruns {
  uint32_t hash_regrids = 0;
  uint32_t grid_reruns = 0;
};

// One grid frame as the pipeline runs it: build and query on the host's plan, read the
// device totals back, re-run on a larger plan until they fit; returns the re-runs.
template <class Exec>
uint32_t run_grid_frame(Exec& exec, UniformGrid<Exec>& grid, uint32_t n, const PairSink& sink) {
  for (uint32_t reruns = 0;; ++reruns) {
    grid_build(exec, grid, n);
    exec.fill(sink.count, 1, 0ull);
    grid_pairs(exec, grid, n, sink);
    GridTotals totals{};
    exec.copy_to_host(&totals, grid.totals.data(), 1);
    if (grid.settle(totals)) return reruns;
  }
}

// A scene's faces and one frame's vertices in the executor's memory, with a pair buffer
// and its counter: what each baseline check runs on.
template <class Exec>
struct DeviceScene {
  DeviceScene(Exec& exec, const Topology& topo)
      : vertices(exec.memory(), "test.vertices"),
        faces(exec.memory(), "test.faces"),
        pairs(exec.memory(), "test.pairs"),
        count(exec.memory(), "test.count"),
        n(uint32_t(topo.faces.size())) {
    vertices.reserve(topo.num_vertices);
    faces.reserve(n);
    count.reserve(1);
    exec.copy_from_host(faces.data(), topo.faces.data(), n);
  }
  // Frame `v` on the executor, as the mesh the baselines read.
  MeshView upload(Exec& exec, const std::vector<vec3f>& v) {
    exec.copy_from_host(vertices.data(), v.data(), v.size());
    return {vertices.data(), faces.data(), n};
  }
  Array<vec3f> vertices;
  Array<Tri> faces;
  Array<PrimPair> pairs;
  Array<unsigned long long> count;
  uint32_t n;
};

// The grid's level and cell count of every box after one frame of `scene`.
struct GridPlacement {
  std::vector<uint32_t> level, cells;
};

template <class Exec>
GridPlacement grid_placement(const SceneFrames& scene) {
  const Topology& topo = scene.topology;
  const uint32_t n = uint32_t(topo.faces.size());
  Exec exec;
  UniformGrid<Exec> grid(exec);
  grid.reserve(exec, n);
  DeviceScene<Exec> d(exec, topo);
  face_boxes(exec, grid, d.upload(exec, scene.frames[0]));
  grid_build(exec, grid, n);
  GridPlacement p{std::vector<uint32_t>(n), std::vector<uint32_t>(n)};
  exec.copy_to_host(p.level.data(), grid.level.data(), n);
  exec.copy_to_host(p.cells.data(), grid.counts.data(), n);
  return p;
}

// The pairs of the boxes every baseline computes from frame `v` with `margin` (face_box,
// rounded outward, so past float range they reach +-inf), tested pair by pair on the host.
inline std::vector<PrimPair> margin_box_pairs(const Topology& topo, const std::vector<vec3f>& v, float margin) {
  const uint32_t n = uint32_t(topo.faces.size());
  MeshView mesh{v.data(), topo.faces.data(), n};
  mesh.margin = margin;
  std::vector<vec4f> lo(n), hi(n);
  for (uint32_t f = 0; f < n; ++f) face_box(mesh, f, lo[f], hi[f]);
  std::vector<PrimPair> pairs;
  for (uint32_t a = 0; a < n; ++a)
    for (uint32_t b = a + 1; b < n; ++b)
      if (overlaps(lo[a], hi[a], lo[b], hi[b])) pairs.push_back({a, b});
  return pairs;
}

// The baselines on every frame. With `tiny_grid_plan`, the grid starts each frame with a
// plan of 1024 entries and 1 key bit, so a frame with more must re-run, never truncate.
// With a `margin`, every box grows by it (as --box-margin grows them) and the expected
// pairs are those of the grown boxes, every pair tested.
template <class Exec>
BaselineReruns check_baselines(const SceneFrames& scene, bool tiny_grid_plan = false, float margin = 0.0f) {
  const Topology& topo = scene.topology;
  const uint32_t n = uint32_t(topo.faces.size());
  Exec exec;
  SweepAndPrune<Exec> sweep(exec);
  SpatialHash<Exec> hash(exec);
  UniformGrid<Exec> grid(exec);
  sweep.reserve(exec, n);
  hash.reserve(exec, n);
  grid.reserve(exec, n);
  DeviceScene<Exec> d(exec, topo);
  Array<PrimPair>& pairs = d.pairs;
  Array<unsigned long long>& count = d.count;
  BaselineReruns reruns;
  for (uint32_t f = 0; f < scene.frames.size(); ++f) {
    const std::vector<vec3f>& v = scene.frames[f];
    MeshView mesh = d.upload(exec, v);
    mesh.margin = margin;
    const std::vector<PrimPair> expected =
        margin == 0.0f ? sweep_oracle_pairs(topo, v) : margin_box_pairs(topo, v, margin);
    pairs.reserve(expected.size() + 1);
    const PairSink sink{pairs.data(), count.data(), pairs.capacity()};

    sweep_boxes(exec, sweep, mesh);
    sweep_sort(exec, sweep, n);
    exec.fill(count.data(), 1, 0ull);
    sweep_pairs(exec, sweep, n, sink);
    expect_pairs(exec, expected, pairs, count, "sweep frame " + std::to_string(f));

    face_boxes(exec, hash, mesh);
    reruns.hash_regrids += hash_build(exec, hash, n);
    exec.fill(count.data(), 1, 0ull);
    hash_pairs(exec, hash, n, sink);
    expect_pairs(exec, expected, pairs, count, "hash frame " + std::to_string(f));

    face_boxes(exec, grid, mesh);
    if (tiny_grid_plan) {
      grid.planned_entries = 1024;
      grid.key_bits = 1;
    }
    reruns.grid_reruns += run_grid_frame(exec, grid, n, sink);
    expect_pairs(exec, expected, pairs, count, "grid frame " + std::to_string(f));
  }
  return reruns;
}

// n triangles at random places in the unit cube, every third with a box of edge `big` on
// each axis and the rest almost points: the mean width sets the hash's cell, so the large
// boxes span 3-4 cells an axis (27-64 entries each, none past kMaxCellsPerBox) and the
// entries run to about twice kEntriesPerBoxEstimate a box. Frame 1 moves everything a little.
inline SceneFrames bimodal_soup(uint32_t n, float big, uint32_t seed) {
  SceneFrames s;
  s.frames.resize(2);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (uint32_t t = 0; t < n; ++t) {
    s.topology.faces.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    const float e = t % 3 == 0 ? big : 1e-6f;
    const vec3f c{unit(rng), unit(rng), unit(rng)};
    for (const vec3f d : {vec3f{e, 0, 0}, vec3f{0, e, 0}, vec3f{0, 0, e}}) {
      s.frames[0].push_back({c.x + d.x, c.y + d.y, c.z + d.z});
      s.frames[1].push_back({c.x + d.x + 0.01f, c.y + d.y, c.z + d.z - 0.01f});
    }
  }
  s.topology.num_vertices = 3 * n;
  return s;
}

// Two passes over the frames, each starting with reserve() as a pipeline's pass does (run
// --repeat): the first grows the entries past the estimate, and the second must size its
// sort for the frame's entries, not for the estimate its reserve() went back to.
template <class Exec>
void check_hash_second_pass(const SceneFrames& scene) {
  const Topology& topo = scene.topology;
  const uint32_t n = uint32_t(topo.faces.size());
  Exec exec;
  SpatialHash<Exec> hash(exec);
  DeviceScene<Exec> d(exec, topo);
  Array<PrimPair>& pairs = d.pairs;
  Array<unsigned long long>& count = d.count;
  size_t most_entries = 0;
  for (int pass = 0; pass < 2; ++pass) {
    hash.reserve(exec, n);
    for (uint32_t f = 0; f < scene.frames.size(); ++f) {
      const std::vector<vec3f>& v = scene.frames[f];
      const MeshView mesh = d.upload(exec, v);
      const std::vector<PrimPair> expected = sweep_oracle_pairs(topo, v);
      pairs.reserve(expected.size() + 1);
      face_boxes(exec, hash, mesh);
      hash_build(exec, hash, n);
      most_entries = std::max<size_t>(most_entries, hash.num_entries);
      exec.fill(count.data(), 1, 0ull);
      hash_pairs(exec, hash, n, PairSink{pairs.data(), count.data(), pairs.capacity()});
      expect_pairs(exec, expected, pairs, count, "hash pass " + std::to_string(pass) + " frame " + std::to_string(f));
    }
  }
  // The scene must outgrow reserve()'s estimate, or the second pass proves nothing.
  EXPECT_GT(most_entries, kEntriesPerBoxEstimate * size_t(n));
}

}  // namespace cdb::test
