#include "baseline_cases.h"
#include "bvh_cases.h"
#include "core/error.h"
#include "exec/host_exec.h"

namespace cdb::test {

class HostSoup : public testing::TestWithParam<SoupCase> {};

TEST_P(HostSoup, TreeValidAndPairsExact) { check_soup_case<HostExec>(GetParam()); }

INSTANTIATE_TEST_SUITE_P(Soups, HostSoup, testing::ValuesIn(soup_cases()), case_name);

class HostBaselines : public testing::TestWithParam<BaselineCase> {};

TEST_P(HostBaselines, SweepAndHashExact) { check_baselines<HostExec>(GetParam().make()); }

INSTANTIATE_TEST_SUITE_P(Scenes, HostBaselines, testing::ValuesIn(baseline_cases()),
                         baseline_case_name);

TEST(HostBaselinesGrid, FewLargeBoxesAreTestedDirectlyManyCoarsenTheGrid) {
  EXPECT_EQ(check_baselines<HostExec>(soup_with_giants(3000, 10, false)), 0u);
  EXPECT_GT(check_baselines<HostExec>(soup_with_giants(3000, 100, false)), 0u);
}

TEST(HostPipelines, ExactOnClothAndFunnelWithGrowingPairBuffer) {
  auto wave = make_generator("cloth-wave", {{"res", 24}, {"frames", 6}});
  check_pipelines_on(config_for("cpu", 0.01), *wave);
  auto funnel = make_generator("funnel", {{"res", 20}, {"frames", 6}, {"segments", 16}, {"ball_level", 1}});
  check_pipelines_on(config_for("cpu", 8.0), *funnel);
}

// Every front operation sequence: update every frame (cycle 1), alternating (2), and
// longer cycles (3, 5: periodic's generate-instead-of-update); fronts that start far too
// small so they must grow while sprouting.
class HostFrontCycles : public testing::TestWithParam<uint32_t> {};

TEST_P(HostFrontCycles, AllPipelinesExactEveryFrame) {
  for (auto& scene : front_scenes(24, 12)) check_pipelines_on(config_for("cpu", 0.5, 0.05, GetParam()), *scene);
}

INSTANTIATE_TEST_SUITE_P(Cycles, HostFrontCycles, testing::Values(1u, 2u, 3u, 5u));

TEST(HostFrontPipelines, RecordTheOperationsOfTheirCycle) {
  auto wave = make_generator("cloth-wave", {{"res", 16}, {"frames", 9}});
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected_ops = {
      {"a", {"build+generate", "refit+preserve", "refit+update", "refit+preserve", "refit+update"}},
      {"periodic", {"build+generate", "refit+preserve", "refit+update", "refit+preserve", "refit+generate"}},
      {"reference", {"build+generate", "build+generate", "build+generate", "build+generate", "build+generate"}},
  };
  for (const auto& [name, ops] : expected_ops) {
    PipelineConfig cfg = config_for("cpu", 8.0, 8.0, 2);
    cfg.name = name;
    auto p = make_pipeline(cfg);
    p->set_topology(wave->topology());
    std::vector<vec3f> v;
    for (uint32_t f = 0; f < ops.size(); ++f) {
      wave->frame(f, v);
      const FrameStats s = p->run_frame(v);
      EXPECT_EQ(s.op, ops[f]) << name << " frame " << f;
      EXPECT_GT(s.front_internal + s.front_external, 0u) << name;
      if (name != "unordered") {
        EXPECT_GT(s.q_root, 0.0) << name;
      }
    }
  }
}

TEST(HostPipelines, PairBufferGrowthIsCountedNotTruncated) {
  auto soup = make_generator("soup", {{"triangles", 500}, {"distribution", "identical"}});
  PipelineConfig cfg;
  cfg.device = "cpu";
  cfg.pairs_per_triangle = 0.0;
  auto p = make_pipeline(cfg);
  p->set_topology(soup->topology());
  std::vector<vec3f> v;
  soup->frame(0, v);
  const FrameStats s = p->run_frame(v);
  EXPECT_EQ(s.pairs, 500ull * 499 / 2);
  EXPECT_GE(s.query_reruns, 1u);
  EXPECT_GE(p->memory().growths, 1u);
  EXPECT_EQ(p->sorted_pairs().size(), 500ull * 499 / 2);
}

TEST(HostPipelines, UnknownPipelineAndDeviceAreErrors) {
  PipelineConfig cfg;
  cfg.device = "cpu";
  cfg.name = "nope";
  EXPECT_THROW(make_pipeline(cfg), Error);
  cfg.name = "bvh";
  cfg.device = "tpu";
  EXPECT_THROW(make_pipeline(cfg), Error);
}

}  // namespace cdb::test
