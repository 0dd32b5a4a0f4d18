// The public API (api/cdbench.h, docs/library.md) on the host executor: every pipeline
// against the oracle, frames read in place against the same frames uploaded through the
// engine (every box option), pairs into a reused vector, buffer allocations, and its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "api_cloth.h"
#include "cdbench/cdbench.h"
#include "error_of.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {
namespace {

constexpr uint32_t kSide = 12;

cdbench::Topology cloth() { return api_cloth(kSide); }
std::vector<float> waving(int frame) { return api_cloth_waving(kSide, frame); }

bool same(const std::vector<PrimPair>& a, const std::vector<PrimPair>& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](PrimPair x, PrimPair y) { return pair_key(x) == pair_key(y); });
}

TEST(Api, EveryPipelineEqualsTheOracleEveryFrame) {
  const cdbench::Topology topology = cloth();
  ASSERT_EQ(cdbench::pipelines(), pipeline_names());
  for (bool skip : {false, true})
    for (const std::string& name : cdbench::pipelines()) {
      cdbench::BroadPhase bp({.pipeline = name, .skip_adjacent = skip}, topology);
      std::vector<cdbench::Pair> pairs;
      for (int f = 0; f < 6; ++f) {
        const std::vector<float> xyz = waving(f);
        const cdbench::FrameStats& s = bp.run(xyz.data(), bp.num_vertices());
        const std::vector<PrimPair> expected = cdbench::oracle_pairs(topology, xyz.data(), xyz.size() / 3, skip);
        ASSERT_FALSE(expected.empty());
        bp.pairs(pairs);
        EXPECT_TRUE(same(pairs, expected)) << name << " frame " << f;
        EXPECT_TRUE(same(bp.pairs(), expected)) << name << " frame " << f;
        EXPECT_EQ(s.pairs, expected.size());
        EXPECT_FALSE(s.op.empty());
      }
    }
}

// A frame's buffer allocations: some on a frame whose pairs outgrow the buffers (the cloth
// shrunk until every box overlaps nearly every other), for every pipeline; none once that
// frame has run before, for the pipelines whose frames do the same work each time (the front
// pipelines' maintenance follows measured times, so their fronts may grow on any frame).
TEST(Api, BufferAllocationsOnlyWhileSizesGrow) {
  constexpr uint32_t side = 24;  // crushed: 1,152 triangles, some 660,000 pairs
  const cdbench::Topology topology = api_cloth(side);
  const std::vector<float> flat = api_cloth_waving(side, 0);
  std::vector<float> crushed = flat;
  for (float& x : crushed) x *= 0.01f;
  const std::vector<std::string> same_work = {"bvh", "sweep", "hash", "grid", "brute"};
  for (const std::string& name : cdbench::pipelines()) {
    cdbench::BroadPhase bp({.pipeline = name}, topology);
    bp.run(flat.data(), bp.num_vertices());
    EXPECT_GT(bp.run(crushed.data(), bp.num_vertices()).buffer_allocations, 0u)
        << name << ": the crushed frame's pairs outgrow the buffers";
    if (std::find(same_work.begin(), same_work.end(), name) == same_work.end()) continue;
    bp.run(crushed.data(), bp.num_vertices());
    EXPECT_EQ(bp.run(crushed.data(), bp.num_vertices()).buffer_allocations, 0u) << name << ": the same frame again";
  }
}

// On the host executor a float frame is read where the caller holds it (FrameVertices
// resident); with swept boxes it is copied for the next frame. Either way the pairs are those
// of the same frames uploaded through the engine, for every box option.
TEST(Api, FramesReadInPlaceEqualUploadedFrames) {
  const cdbench::Topology topology = cloth();
  Topology engine;
  for (const auto& t : topology.triangles) engine.faces.push_back({t.v0, t.v1, t.v2});
  engine.num_vertices = topology.num_vertices;
  for (const char* name : {"c", "bvh", "sweep"})
    for (const char* precision : {"fp32", "q16"})
      for (bool swept : {false, true}) {
        const cdbench::Options o{.pipeline = name, .margin = 0.01f, .swept = swept, .box_precision = precision};
        cdbench::BroadPhase bp(o, topology);
        PipelineConfig c;
        c.name = name;
        c.device = "cpu";
        c.boxes = {o.margin, swept, parse_box_precision(precision)};
        auto uploaded = make_pipeline(c);
        uploaded->set_topology(engine);
        // The caller's buffer is overwritten each frame, as a simulator's is.
        std::vector<float> xyz;
        for (int f = 0; f < 5; ++f) {
          xyz = waving(f);
          std::vector<vec3f> v(xyz.size() / 3);
          std::memcpy(v.data(), xyz.data(), xyz.size() * sizeof(float));
          bp.run(xyz.data(), v.size());
          uploaded->run_frame(v);
          EXPECT_TRUE(same(bp.pairs(), uploaded->sorted_pairs()))
              << name << " " << precision << (swept ? " swept" : "") << " frame " << f;
        }
      }
}

TEST(Api, DoublesBoxesAndQueries) {
  const cdbench::Topology topology = cloth();
  const std::vector<float> xyz = waving(3);
  const std::vector<double> doubles(xyz.begin(), xyz.end());
  cdbench::BroadPhase bp({.pipeline = "c"}, topology);
  bp.run(doubles.data(), doubles.size() / 3);
  EXPECT_TRUE(same(bp.pairs(), cdbench::oracle_pairs(topology, xyz.data(), xyz.size() / 3)));

  // Three boxes: 0 and 1 overlap, 2 touches 1 at a face (closed boxes: a pair), 0 and 2 apart.
  const cdbench::Topology boxes = cdbench::Topology::boxes(3);
  const std::vector<float> corners = {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 2, 2, 2, 2, 0, 0, 3, 1, 1};
  cdbench::BroadPhase bb({.pipeline = "grid"}, boxes);
  bb.run(corners.data(), 6);
  EXPECT_TRUE(same(bb.pairs(), {{0, 1}, {1, 2}}));
  EXPECT_TRUE(same(cdbench::oracle_pairs(boxes, corners.data(), 6), {{0, 1}, {1, 2}}));

  cdbench::Topology split = topology;
  const uint32_t half = uint32_t(split.triangles.size() / 2);
  split.objects = {{"top", 0, half}, {"bottom", half, uint32_t(split.triangles.size()) - half}};
  split.inter_queries = {{0, 1}};
  cdbench::BroadPhase bs({.pipeline = "c"}, split);
  bs.run(xyz.data(), xyz.size() / 3);
  const std::vector<PrimPair> expected = cdbench::oracle_pairs(split, xyz.data(), xyz.size() / 3);
  ASSERT_FALSE(expected.empty());
  for (PrimPair p : expected) EXPECT_TRUE(p.a < half && p.b >= half);
  EXPECT_TRUE(same(bs.pairs(), expected));
}

TEST(Api, ErrorsInTheLibrarysWords) {
  const cdbench::Topology topology = cloth();
  EXPECT_EQ(error_of([&] { cdbench::BroadPhase({.pipeline = "d"}, topology); }).rfind("unknown pipeline 'd' (known: bvh, ", 0), 0u);
  EXPECT_EQ(error_of([&] { cdbench::BroadPhase({.executor = "gpu"}, topology); }), "unknown device 'gpu' (known: cuda, cpu)");
  EXPECT_EQ(error_of([] { cdbench::BroadPhase({}, cdbench::Topology::mesh({{0, 1, 3}}, 3)); }),
            "triangle 0 has vertex 3, but the topology has 3 vertices (0-based)");
  cdbench::Topology queries = topology;
  queries.self_queries = {0};
  EXPECT_EQ(error_of([&] { cdbench::BroadPhase({}, queries); }), "queries are declared, but the topology has no objects");
  cdbench::BroadPhase bp({.pipeline = "sweep"}, topology);
  const std::vector<float> xyz = waving(0);
  EXPECT_EQ(error_of([&] { bp.run(xyz.data(), 5); }), "frame has 5 vertices, topology has 169");
  EXPECT_EQ(error_of([&] { bp.run_device(xyz.data(), 169); }),
            "run_device: the executor is cpu; device memory needs executor cuda");
  EXPECT_EQ(error_of([&] { bp.device_pairs(); }).rfind("device_pairs: the executor is cpu", 0), 0u);
  std::string reason;
  if (!cdbench::cuda_available(&reason)) {
    EXPECT_FALSE(reason.empty());
    EXPECT_EQ(error_of([&] { cdbench::BroadPhase({.executor = "cuda"}, topology); }).rfind("--device cuda: ", 0), 0u);
  }
}

}  // namespace
}  // namespace cdb::test
