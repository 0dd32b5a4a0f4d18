// The example pipeline (docs/extending.md "Adding a pipeline") on the host executor.
#include "example_cases.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

class HostExample : public testing::TestWithParam<BaselineCase> {};

TEST_P(HostExample, ExactAgainstTheOracleEveryFrame) { check_example_pipeline("cpu", GetParam().make()); }

INSTANTIATE_TEST_SUITE_P(Scenes, HostExample, testing::ValuesIn(example_cases()), baseline_case_name);

// 300 triangles at one point: 44850 pairs against a first buffer of 1024, so the first
// frame grows it and re-runs; the second frame starts from the grown buffer and does not.
TEST(HostExample, GrowsItsPairBufferAndRunsTheQueryAgain) {
  PipelineConfig cfg;
  cfg.name = kExamplePipeline;
  cfg.device = "cpu";
  cfg.capacity.pairs_per_triangle = 0.25;
  const SceneFrames scene = all_at_one_point(300, 0.25f);
  auto p = make_pipeline(cfg);
  p->set_topology(scene.topology);
  const FrameStats first = p->run_frame(scene.frames[0]);
  EXPECT_EQ(first.timing.query_reruns, 1u);
  EXPECT_EQ(first.pairs, 300u * 299u / 2u);
  EXPECT_EQ(first.timing.host_syncs, 2u);  // the counters' read-back, once more after the growth
  const FrameStats second = p->run_frame(scene.frames[1]);
  EXPECT_EQ(second.timing.query_reruns, 0u);
  EXPECT_EQ(second.timing.host_syncs, 1u);
  EXPECT_EQ(p->sorted_pairs().size(), 300u * 299u / 2u);
  EXPECT_EQ(p->memory().growths, 1u);
}

// The table marks it as an example, and it keeps no boxes between frames.
TEST(HostExample, ListedAsAnExampleAndConservative) {
  const PipelineKind* kind = find_pipeline_kind(kExamplePipeline);
  ASSERT_NE(kind, nullptr);
  EXPECT_EQ(std::string(kind->description).rfind("EXAMPLE", 0), 0u) << kind->description;
  EXPECT_EQ(pipeline_names().back(), kExamplePipeline);
  PipelineConfig cfg;
  cfg.name = kExamplePipeline;
  cfg.tree.refit_every = 4;
  EXPECT_TRUE(config_conservative(cfg));
}

// Declared queries and the box options reach it as they reach every pipeline: the
// skip-adjacent and query filters through the pair sink, fat boxes through face_box.
TEST(HostExample, FatBoxesGiveTheInflatedOraclePairs) {
  const SceneFrames scene = frames_of(*make_generator("soup", {{"triangles", 2000}, {"frames", 2}, {"seed", 3}}));
  PipelineConfig exact_cfg, fat_cfg;
  exact_cfg.name = fat_cfg.name = kExamplePipeline;
  exact_cfg.device = fat_cfg.device = "cpu";
  fat_cfg.boxes.margin = 0.01f;
  PipelineConfig brute_cfg = fat_cfg;
  brute_cfg.name = oracle_pipeline();
  auto exact = make_pipeline(exact_cfg), fat = make_pipeline(fat_cfg), brute = make_pipeline(brute_cfg);
  for (auto* p : {exact.get(), fat.get(), brute.get()}) p->set_topology(scene.topology);
  for (const auto& v : scene.frames) {
    exact->run_frame(v);
    fat->run_frame(v);
    brute->run_frame(v);
    const std::vector<PrimPair> fat_pairs = fat->sorted_pairs();
    EXPECT_TRUE(diff_pair_sets(brute->sorted_pairs(), fat_pairs).equal());
    EXPECT_GT(fat_pairs.size(), exact->sorted_pairs().size());
  }
}

}  // namespace cdb::test
