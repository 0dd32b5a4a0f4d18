#pragma once
// The property tests of the ordered LBVH and its self query, written once over the
// executor; test_bvh_host.cpp runs them on the host executor, test_bvh_cuda.cu on CUDA.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "bruteforce/sweep_oracle.h"
#include "bvh/build.h"
#include "bvh/order.h"
#include "bvh/refit.h"
#include "bvh/self_query.h"
#include "bvh_checks.h"
#include "core/pair_set.h"
#include "generators.h"
#include "pipeline/pipeline.h"

namespace cdb::test {

struct SoupCase {
  uint64_t triangles;
  std::string distribution;
  double scale;
  double duplicates;
  MortonBits bits;
};

inline std::string case_name(const testing::TestParamInfo<SoupCase>& info) {
  const SoupCase& c = info.param;
  std::string s = "n" + std::to_string(c.triangles) + "_" + c.distribution;
  s += c.scale == 1.0 ? "_unit" : c.scale < 1.0 ? "_tiny" : "_huge";
  if (c.duplicates > 0) s += "_dups";
  s += c.bits == MortonBits::b30 ? "_m30" : "_m63";
  return s;
}

// Sizes 0..100000 over uniform, clustered and identical centroids, duplicates, and
// coordinates scaled to 1e-20 and 1e+20. Identical centroids make every box overlap every
// other (N^2/2 pairs), so they stop at 2000 triangles.
inline std::vector<SoupCase> soup_cases() {
  std::vector<SoupCase> cases;
  for (uint64_t n : {0ull, 1ull, 2ull, 3ull, 7ull, 1000ull, 100000ull})
    for (const char* dist : {"uniform", "clustered", "identical"})
      for (double scale : {1.0, 1e-20, 1e20}) {
        if (std::string(dist) == "identical" && n > 2000) continue;
        const bool small_variant = scale != 1.0 && n == 100000;
        if (small_variant) continue;  // scale variants run at 1000 and below
        cases.push_back({n, dist, scale, 0.0, MortonBits::b63});
      }
  cases.push_back({2000, "identical", 1.0, 0.0, MortonBits::b63});
  cases.push_back({1000, "uniform", 1.0, 0.3, MortonBits::b63});
  cases.push_back({1000, "clustered", 1.0, 0.5, MortonBits::b30});
  cases.push_back({100000, "uniform", 1.0, 0.1, MortonBits::b30});
  cases.push_back({100000, "clustered", 1e20, 0.0, MortonBits::b30});
  return cases;
}

inline std::unique_ptr<FrameSource> soup_source(const SoupCase& c) {
  return make_generator("soup", {{"triangles", c.triangles},
                                 {"distribution", c.distribution},
                                 {"scale", c.scale},
                                 {"duplicates", c.duplicates},
                                 {"frames", 3},
                                 {"seed", 11 + c.triangles}});
}

// Build + order on frame 0, refit on frames 1 and 2: after each, the tree must pass every
// reference check and the self query must report exactly the oracle's pairs.
template <class Exec>
void check_soup_case(const SoupCase& c) {
  auto source = soup_source(c);
  const Topology& topo = source->topology();
  Exec exec;
  Lbvh<Exec> bvh(exec);
  Array<vec3f> vertices(exec.memory(), "test.vertices");
  Array<Tri> faces(exec.memory(), "test.faces");
  Array<PrimPair> pairs(exec.memory(), "test.pairs");
  Array<unsigned long long> count(exec.memory(), "test.count");
  vertices.reserve(topo.num_vertices);
  faces.reserve(topo.faces.size());
  count.reserve(1);
  exec.copy_from_host(faces.data(), topo.faces.data(), topo.faces.size());
  std::vector<vec3f> v;
  for (uint32_t f = 0; f < source->num_frames(); ++f) {
    source->frame(f, v);
    exec.copy_from_host(vertices.data(), v.data(), v.size());
    const MeshView mesh{vertices.data(), faces.data(), uint32_t(topo.faces.size())};
    if (f == 0) {
      build_hierarchy(exec, bvh, mesh, c.bits);
      order_depth_first(exec, bvh);
    } else {
      refit(exec, bvh, mesh);
    }
    const HostBvh h = download(exec, bvh);
    ASSERT_EQ(check_bvh(h, topo, v), "") << "frame " << f;

    const std::vector<PrimPair> expected = sweep_oracle_pairs(topo, v);
    pairs.reserve(expected.size() + 1);
    exec.fill(count.data(), 1, 0ull);
    self_query(exec, bvh.view(), PairSink{pairs.data(), count.data(), pairs.capacity()});
    unsigned long long found = 0;
    exec.copy_to_host(&found, count.data(), 1);
    ASSERT_EQ(found, expected.size()) << "frame " << f;
    std::vector<PrimPair> got(found);
    exec.copy_to_host(got.data(), pairs.data(), found);
    std::sort(got.begin(), got.end(), [](PrimPair a, PrimPair b) { return pair_key(a) < pair_key(b); });
    const PairSetDiff d = diff_pair_sets(expected, got);
    ASSERT_TRUE(d.equal()) << "frame " << f << ": " << d.missing_count << " missing, "
                           << d.unexpected_count << " unexpected";
  }
}

// Every pipeline, through the public factory, on every frame of a scene, against the
// sweep oracle; with a pair buffer far too small at the start so it must grow. The O(N^2)
// brute pipeline joins only up to brute_limit triangles.
inline void check_pipelines_on(const PipelineConfig& base, FrameSource& source,
                               size_t brute_limit = 100000) {
  const Topology& topo = source.topology();
  std::vector<std::string> names;
  std::vector<std::unique_ptr<Pipeline>> pipelines;
  for (const auto& name : pipeline_names()) {
    if (name == oracle_pipeline() && topo.faces.size() > brute_limit) continue;
    PipelineConfig cfg = base;
    cfg.name = name;
    names.push_back(name);
    pipelines.push_back(make_pipeline(cfg));
    pipelines.back()->set_topology(topo);
  }
  std::vector<vec3f> v;
  for (uint32_t f = 0; f < source.num_frames(); ++f) {
    source.frame(f, v);
    const auto expected = sweep_oracle_pairs(topo, v);
    for (size_t p = 0; p < pipelines.size(); ++p) {
      const FrameStats s = pipelines[p]->run_frame(v);
      ASSERT_EQ(s.pairs, expected.size()) << names[p] << " frame " << f << " (" << s.op << ")";
      const PairSetDiff d = diff_pair_sets(expected, pipelines[p]->sorted_pairs());
      ASSERT_TRUE(d.equal()) << names[p] << " frame " << f << " (" << s.op << "): " << d.missing_count
                             << " missing, " << d.unexpected_count << " unexpected";
    }
  }
}

inline PipelineConfig config_for(const std::string& device, double pairs_per_triangle,
                                 double front_per_triangle = 8.0, uint32_t front_cycle = 4) {
  PipelineConfig c;
  c.device = device;
  c.pairs_per_triangle = pairs_per_triangle;
  c.front_per_triangle = front_per_triangle;
  c.front_cycle = front_cycle;
  return c;
}

// Scenes whose motion makes fronts sprout and prune: a rolling cloth, the funnel, and a
// soup whose jitter is larger than its triangles.
inline std::vector<std::unique_ptr<FrameSource>> front_scenes(uint32_t cloth_res, uint32_t frames) {
  std::vector<std::unique_ptr<FrameSource>> s;
  s.push_back(make_generator("cloth-wave", {{"res", cloth_res}, {"frames", frames}}));
  s.push_back(make_generator(
      "funnel", {{"res", cloth_res}, {"frames", frames}, {"segments", 16}, {"ball_level", 1}}));
  s.push_back(make_generator("soup", {{"triangles", 3000}, {"distribution", "clustered"},
                                      {"jitter", 3.0}, {"frames", frames}, {"seed", 5}}));
  return s;
}

}  // namespace cdb::test
