#pragma once
// Property tests of the sweep and hash baselines, written once over the executor: on
// nasty soups and on boxes touching exactly along grid-cell boundaries, each must report
// exactly the sweep oracle's pairs on every frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "bruteforce/sweep_oracle.h"
#include "core/pair_set.h"
#include "generators.h"
#include "hash/spatial_hash.h"
#include "sweep/sweep.h"

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

struct BaselineCase {
  std::string name;
  std::function<SceneFrames()> make;
};

inline void PrintTo(const BaselineCase& c, std::ostream* os) { *os << c.name; }

inline std::string baseline_case_name(const testing::TestParamInfo<BaselineCase>& info) {
  return info.param.name;
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
  cases.push_back({"cubes_unit_8", [] { return cube_lattice(8, 1.0f); }});
  cases.push_back({"cubes_tiny_5", [] { return cube_lattice(5, 0x1p-70f); }});
  cases.push_back({"cubes_huge_5", [] { return cube_lattice(5, 0x1p60f); }});
  cases.push_back({"giants_10", [] { return soup_with_giants(3000, 10, false); }});
  cases.push_back({"giants_100", [] { return soup_with_giants(3000, 100, false); }});
  cases.push_back({"giants_far_5", [] { return soup_with_giants(1000, 5, true); }});
  cases.push_back({"giants_far_60", [] { return soup_with_giants(1000, 60, true); }});
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
  std::sort(got.begin(), got.end(),
            [](PrimPair a, PrimPair b) { return pair_key(a) < pair_key(b); });
  const PairSetDiff d = diff_pair_sets(expected, got);
  ASSERT_TRUE(d.equal()) << what << ": " << d.missing_count << " missing, "
                         << d.unexpected_count << " unexpected";
}

// Both baselines on every frame; returns how often the hash had to coarsen its grid.
template <class Exec>
uint32_t check_baselines(const SceneFrames& scene) {
  const Topology& topo = scene.topology;
  const uint32_t n = uint32_t(topo.faces.size());
  Exec exec;
  SweepAndPrune<Exec> sweep(exec);
  SpatialHash<Exec> hash(exec);
  sweep.reserve(exec, n);
  hash.reserve(exec, n);
  Array<vec3f> vertices(exec.memory(), "test.vertices");
  Array<Tri> faces(exec.memory(), "test.faces");
  Array<PrimPair> pairs(exec.memory(), "test.pairs");
  Array<unsigned long long> count(exec.memory(), "test.count");
  vertices.reserve(topo.num_vertices);
  faces.reserve(n);
  count.reserve(1);
  exec.copy_from_host(faces.data(), topo.faces.data(), n);
  uint32_t regrids = 0;
  for (uint32_t f = 0; f < scene.frames.size(); ++f) {
    const std::vector<vec3f>& v = scene.frames[f];
    exec.copy_from_host(vertices.data(), v.data(), v.size());
    const MeshView mesh{vertices.data(), faces.data(), n};
    const std::vector<PrimPair> expected = sweep_oracle_pairs(topo, v);
    pairs.reserve(expected.size() + 1);
    const PairSink sink{pairs.data(), count.data(), pairs.capacity()};

    sweep_boxes(exec, sweep, mesh);
    sweep_sort(exec, sweep, n);
    exec.fill(count.data(), 1, 0ull);
    sweep_pairs(exec, sweep, n, sink);
    expect_pairs(exec, expected, pairs, count, "sweep frame " + std::to_string(f));

    hash_boxes(exec, hash, mesh);
    regrids += hash_build(exec, hash, n);
    exec.fill(count.data(), 1, 0ull);
    hash_pairs(exec, hash, n, sink);
    expect_pairs(exec, expected, pairs, count, "hash frame " + std::to_string(f));
  }
  return regrids;
}

}  // namespace cdb::test
