// The host property tests, run on the CUDA executor (ctest label gpu). Without a GPU each
// test is reported as skipped, with the reason, never as passed.
#include "baseline_cases.h"
#include "bvh_cases.h"
#include "cell_cases.h"
#include "example_cases.h"
#include "inter_cases.h"
#include "knob_cases.h"
#include "precision_cases.h"
#include "offset_cases.h"
#include "scan_cases.h"
#include "tile_cases.h"
#include "scenes/load/scene.h"
#include "cdbench/exec/cuda_exec.cuh"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

namespace {
// Why these tests cannot run here, or empty when a GPU is present.
std::string missing_gpu() {
  const CudaDeviceInfo info = cuda_device_info();
  return info.available ? "" : "no GPU here (" + info.reason + "); run on the device";
}

// The fixture of every suite here (Base: testing::Test or testing::TestWithParam<Case>):
// without a GPU each test is skipped with the reason.
template <class Base>
class OnGpu : public Base {
 protected:
  void SetUp() override {
    if (const auto why = missing_gpu(); !why.empty()) GTEST_SKIP() << why;
  }
};
}  // namespace

class CudaSoup : public OnGpu<testing::TestWithParam<SoupCase>> {};

TEST_P(CudaSoup, TreeValidAndPairsExact) { check_soup_case<CudaExec>(GetParam()); }

TEST_P(CudaSoup, RadixOrderGivesTheHistogramOrder) { check_radix_order_matches<CudaExec>(GetParam()); }

// Piece ordered builds: falling spheres and cones (each its own piece), a soup (every
// triangle one, 1200), and the funnel (its cloth and its funnel), in 63- and 30-bit keys.
TEST(CudaPieces, EachPieceSpansOneSubtree) {
  for (MortonBits bits : {MortonBits::b63, MortonBits::b30}) {
    EXPECT_EQ(check_piece_order<CudaExec>(*make_generator("n-body", {{"spheres", 40}, {"cones", 3}, {"sphere_level", 1},
                                                                {"frames", 6}, {"warmup", 0}}),
                                     bits), 43u);
    EXPECT_EQ(check_piece_order<CudaExec>(*make_generator("soup", {{"triangles", 1200}, {"frames", 2}, {"seed", 3}}), bits),
              1200u);
    EXPECT_GE(check_piece_order<CudaExec>(*make_generator("funnel", {{"res", 20}, {"frames", 6}}), bits), 2u);
  }
}

INSTANTIATE_TEST_SUITE_P(Soups, CudaSoup, testing::ValuesIn(soup_cases()), case_name);

class CudaBaselines : public OnGpu<testing::TestWithParam<BaselineCase>> {};

TEST_P(CudaBaselines, SweepHashAndGridExact) { check_baselines<CudaExec>(GetParam().make()); }

INSTANTIATE_TEST_SUITE_P(Scenes, CudaBaselines, testing::ValuesIn(baseline_cases()),
                         baseline_case_name);

class CudaExample : public OnGpu<testing::TestWithParam<BaselineCase>> {};

TEST_P(CudaExample, ExactAgainstTheOracleEveryFrame) { check_example_pipeline("cuda", GetParam().make()); }

INSTANTIATE_TEST_SUITE_P(Scenes, CudaExample, testing::ValuesIn(example_cases()), baseline_case_name);

class CudaCells : public OnGpu<testing::Test> {};

TEST_F(CudaCells, CoordinateMonotoneAtExtremes) { check_cell_coord_monotone_at_extremes<CudaExec>(); }

TEST_F(CudaCells, BoxRangesHoldTheirPointsAndHomeCells) {
  check_box_ranges_hold_their_points_and_homes<CudaExec>();
}

TEST_F(CudaCells, OnePointSceneIsOneCell) { check_one_point_scene_is_one_cell<CudaExec>(); }

TEST_F(CudaCells, SceneStatsReduction) { check_scene_stats_reduction<CudaExec>(); }

class CudaExecScan : public OnGpu<testing::Test> {};

TEST_F(CudaExecScan, PairMatchesTheSerialScans) {
  check_exclusive_scan_pair<CudaExec>();
}

class CudaExecTiles : public OnGpu<testing::Test> {};

TEST_F(CudaExecTiles, EveryIndexOnceInItsTile) {
  check_for_each_tile<CudaExec>();
}

class CudaHashBaseline : public OnGpu<testing::Test> {};

TEST_F(CudaHashBaseline, FewLargeBoxesAreTestedDirectlyManyCoarsenTheGrid) {
  EXPECT_EQ(check_baselines<CudaExec>(soup_with_giants(3000, 10, false)).hash_regrids, 0u);
  EXPECT_GT(check_baselines<CudaExec>(soup_with_giants(3000, 100, false)).hash_regrids, 0u);
}

class CudaCellBaselines : public OnGpu<testing::Test> {};

TEST_F(CudaCellBaselines, ExactAtFloatLimitAndPastItToInfinity) {
  check_baselines<CudaExec>(float_limit_boxes(300, 3));
  check_baselines<CudaExec>(float_limit_boxes(300, 3), false, 1e38f);
  check_baselines<CudaExec>(float_limit_boxes(300, 3), true, 1e37f);
}

TEST_F(CudaHashBaseline, SecondPassSortsTheEntriesTheFirstGrewTo) {
  check_hash_second_pass<CudaExec>(bimodal_soup(3000, 0.05f, 7));
}

class CudaGridBaseline : public OnGpu<testing::Test> {};

// The grid plans its sort from the last frame: steady frames fit the plan; a plan far too
// small (1024 entries, 1 key bit) makes each frame re-run once, exactly, never truncate.
TEST_F(CudaGridBaseline, PlanFromTheLastFrameReRunsWhenShort) {
  auto soup = [] {
    return frames_of(*make_generator("soup", {{"triangles", 20000}, {"frames", 4}, {"seed", 9}}));
  };
  EXPECT_EQ(check_baselines<CudaExec>(soup()).grid_reruns, 0u);
  EXPECT_EQ(check_baselines<CudaExec>(soup(), true).grid_reruns, 4u);
  EXPECT_EQ(check_baselines<CudaExec>(multiscale_soup(5000, 4), true).grid_reruns, 2u);
}

// A scene-spanning triangle goes to a coarse level in a few cells, the small ones to the
// finest levels; no box covers more than kGridMaxCellsPerBox cells, however wide.
TEST_F(CudaGridBaseline, WideBoxesGoToCoarserLevelsInFewCells) {
  for (bool far : {false, true}) {
    const GridPlacement p = grid_placement<CudaExec>(soup_with_giants(3000, 1, far));
    const uint32_t small = *std::max_element(p.level.begin(), p.level.end() - 1);
    EXPECT_LE(small, 1u) << far;
    EXPECT_GE(p.level.back(), small + 2) << far;
    for (uint32_t c : p.cells) ASSERT_LE(c, kGridMaxCellsPerBox) << far;
  }
  const GridPlacement m = grid_placement<CudaExec>(multiscale_soup(5000, 3));
  EXPECT_GE(*std::max_element(m.level.begin(), m.level.end()), 2u);
  for (uint32_t c : m.cells) ASSERT_LE(c, kGridMaxCellsPerBox);
}

// Through the pipeline: a frame whose entries outgrow the plan made from the last frame is
// re-run (op regrid) and exact; the next frame plans from it and runs once.
TEST_F(CudaGridBaseline, PipelineReRunsAFrameThatOutgrowsItsPlan) {
  const std::vector<std::string> ops = grid_pipeline_ops("cuda", straddling_pairs(10));
  EXPECT_EQ(ops, (std::vector<std::string>{"grid", "regrid", "grid"}));
}

class CudaPipelines : public OnGpu<testing::Test> {};

TEST_F(CudaPipelines, ExactOnClothAndFunnelWithGrowingPairBuffer) {
  auto wave = make_generator("cloth-wave", {{"res", 64}, {"frames", 8}});
  check_pipelines_on(config_for("cuda", 0.01), *wave);
  auto funnel = make_generator("funnel", {{"res", 48}, {"frames", 20}});
  check_pipelines_on(config_for("cuda", 8.0), *funnel);
}

class CudaKnobs : public OnGpu<testing::Test> {};

// The speed/accuracy knobs (knob_cases.h): face_box's margin and swept boxes run in the
// kernels exactly as the host reference computes them; lazy refits keep stale boxes.
TEST_F(CudaKnobs, OutwardRoundingGivesTheHostsBits) {
  check_outward_rounding_on_executor<CudaExec>(2000000);
}

TEST_F(CudaKnobs, MarginGivesExactlyTheInflatedBoxPairs) {
  auto soup = fast_soup(5);
  check_margin("cuda", *soup, 0.25f * mean_box_extent(*soup));
  auto cloth = rolling_cloth(5);
  check_margin("cuda", *cloth, 0.5f * mean_box_extent(*cloth));
}

TEST_F(CudaKnobs, SweptGivesExactlyTheSweptBoxPairs) {
  auto soup = fast_soup(5);
  check_swept("cuda", *soup);
  auto cloth = rolling_cloth(5);
  check_swept("cuda", *cloth);
}

TEST_F(CudaKnobs, LazyRefitKeepsTheLastRefitsBoxesAndMissesPairs) {
  auto soup = fast_soup(7);
  check_lazy_refit("cuda", *soup, 3);
}

// q16 boxes (precision_cases.h): the grid reduced in kernels equals the host's bit for bit,
// and every pipeline's kernels snap exactly as the host face_box does.
class CudaPrecision : public OnGpu<testing::TestWithParam<BaselineCase>> {};

TEST_P(CudaPrecision, ExecutorGridEqualsTheHostGrid) {
  const SceneFrames s = GetParam().make();
  check_executor_grid<CudaExec>(s, false);
  check_executor_grid<CudaExec>(s, true);
}

TEST_P(CudaPrecision, EveryPipelineReportsExactlyTheQ16Overlaps) {
  size_t extra = 0;
  check_q16_pipelines("cuda", GetParam().make(), extra);
}

INSTANTIATE_TEST_SUITE_P(Scenes, CudaPrecision, testing::ValuesIn(precision_cases()), baseline_case_name);

// Millimetre sheets far from the origin (offset_cases.h) through every pipeline's kernels.
class CudaOffsets : public OnGpu<testing::TestWithParam<OffsetCase>> {};

TEST_P(CudaOffsets, Fp64KeepsEveryPairOfTheDoubleGeometry) { check_fp64_offset("cuda", GetParam().offset); }
TEST_P(CudaOffsets, Fp32KeepsEveryPairButBlursAndWarns) { check_fp32_offset("cuda", GetParam().offset); }

INSTANTIATE_TEST_SUITE_P(Sheets, CudaOffsets, testing::ValuesIn(offset_cases()), offset_case_name);

TEST_F(CudaKnobs, Q16AddsPairsAndCombinesWithMarginAndSweptBoxes) {
  size_t coarse = 0, swept = 0;
  check_q16_pipelines("cuda", with_point_at(cube_lattice(3, 1e-3f), 1e6f), coarse);
  EXPECT_GT(coarse, 0u);
  auto soup = fast_soup(4);
  check_q16_pipelines("cuda", frames_of(*soup), swept, 0.1f * mean_box_extent(*soup), true);
  EXPECT_GT(swept, 0u);
}

TEST_F(CudaPipelines, DeclaredQueriesReportOnlyWhatTheSceneAsks) {
  Scene s = open_scene("funnel-inter", default_scenes_dir(), {{"res", 48}, {"frames", 8}});
  check_declared_queries("cuda", *s.source);
}

TEST_F(CudaPipelines, SkipAdjacentMatchesTheFilteredOracle) {
  auto wave = make_generator("cloth-wave", {{"res", 96}, {"frames", 8}});
  check_skip_adjacent("cuda", *wave);
  auto funnel = make_generator("funnel", {{"res", 48}, {"frames", 8}});
  check_skip_adjacent("cuda", *funnel);
}

// The radix baseline once failed here: its sort storage was re-sized for the initial
// capacity while its keys kept the grown one.
TEST_F(CudaPipelines, SecondPassAfterGrowthMatchesTheFirst) {
  auto funnel = make_generator("funnel", {{"res", 40}, {"frames", 6}, {"segments", 16}, {"ball_level", 1}});
  check_second_pass_matches_first(config_for("cuda", 0.01, 0.05, 2), *funnel);
}

// Many rebuilds of a scene of many blocks: a missing fence in the bottom-up build shows up
// as an occasional corrupt tree, so repeat. 2^16 + 1 triangles: one past a power of two,
// so the last block and tile hold a single triangle. CudaLong repeats it at 1M.
TEST_F(CudaPipelines, UniformSoupRepeatedBuildsAreExact) {
  auto soup = make_generator("soup", {{"triangles", (1 << 16) + 1}, {"frames", 4}});
  check_pipelines_on(config_for("cuda", 8.0), *soup);
}

// --cuda-graph: steady frames are captured once after each front change and replayed
// after; the replays report the same pairs as plain launches, and still time their phases.
TEST_F(CudaPipelines, GraphReplaysGiveThePlainLaunchesPairs) {
  auto funnel = make_generator("funnel", {{"res", 40}, {"frames", 14}, {"segments", 16}, {"ball_level", 1}});
  const Topology& topo = funnel->topology();
  for (const std::string name : {"a", "b", "c", "unordered"}) {
    for (bool swept : {false, true}) {
      PipelineConfig with = config_for("cuda", 0.05, 0.05, 6), without = with;
      with.name = without.name = name;
      with.boxes.swept = without.boxes.swept = swept;
      with.launch.cuda_graph = true;
      without.launch.cuda_graph = false;
      auto graphed = make_pipeline(with), plain = make_pipeline(without);
      graphed->set_topology(topo);
      plain->set_topology(topo);
      std::vector<vec3f> v;
      uint32_t captured = 0, replayed = 0;
      for (uint32_t f = 0; f < funnel->num_frames(); ++f) {
        funnel->frame(f, v);
        const FrameStats g = graphed->run_frame(v), p = plain->run_frame(v);
        EXPECT_EQ(p.timing.graph, "");
        captured += g.timing.graph == "captured";
        replayed += g.timing.graph == "replayed";
        if (!g.timing.graph.empty()) {
          EXPECT_GT(g.timing.phase_ms[size_t(Phase::preserve)], 0.0) << name << " frame " << f;
          EXPECT_GT(g.timing.phase_ms[size_t(Phase::refit)], 0.0) << name << " frame " << f;
        }
        ASSERT_EQ(g.pairs, p.pairs) << name << " frame " << f;
        ASSERT_TRUE(diff_pair_sets(plain->sorted_pairs(), graphed->sorted_pairs()).equal())
            << name << (swept ? " swept" : "") << " frame " << f;
      }
      // 14 frames, cycle 6: preserve on frames 1-5, 7-11 and 13, all steady; each run of them
      // captures first (swept boxes alternate two vertex buffers: twice; a buffer that grew:
      // again), then replays; the probes before the updates (frames 5 and 11) launch plain.
      // Pipeline c may turn a preserve into a restructure.
      if (name != "c") {
        EXPECT_EQ(captured + replayed, 9u) << name;
        EXPECT_GE(replayed, swept ? 2u : 5u) << name;
      }
    }
  }
}

TEST_F(CudaKnobs, DependentLaunchesAndUntimedPhasesKeepEveryPipelineExact) {
  for (bool graph : {false, true})
    for (bool dependent : {false, true}) check_launch_knobs("cuda", graph, dependent);
}

TEST_F(CudaKnobs, PieceOrderedBuildsKeepEveryPipelineExact) { check_build_pieces("cuda"); }

TEST_F(CudaKnobs, UpdateVariantsKeepEveryPipelineExact) {
  check_update_knobs("cuda");
}

TEST_F(CudaKnobs, PairBufferGrowsBetweenFrames) {
  check_pairs_grown_ahead("cuda");
}

TEST_F(CudaKnobs, ProbedUpdatesRunOnce) {
  check_update_probe("cuda");
}

TEST_F(CudaKnobs, ProbeCountsMatchTheHost) {
  check_probe_counts("cuda");
}

// Every front cycle (1, 2, 3, 5 and auto) on each front scene, against the scene's oracle
// pairs computed once.
class CudaFrontCycles : public OnGpu<testing::TestWithParam<std::string>> {};

TEST_P(CudaFrontCycles, AllPipelinesExactEveryFrame) { check_front_cycles("cuda", GetParam(), 96, 16); }

INSTANTIATE_TEST_SUITE_P(Scenes, CudaFrontCycles, testing::ValuesIn(front_scene_names()), front_scene_name);

class CudaExtremes : public OnGpu<testing::TestWithParam<BaselineCase>> {};

TEST_P(CudaExtremes, EveryPipelineExactEveryFrame) {
  StoredFrames scene(GetParam().make());
  check_pipelines_on(config_for("cuda", 0.5, 0.05, 1), scene);
}

INSTANTIATE_TEST_SUITE_P(Scenes, CudaExtremes, testing::ValuesIn(extreme_cases()), baseline_case_name);

class CudaRefit : public OnGpu<testing::Test> {};

TEST_F(CudaRefit, TopInOneBlockSpillsPastSharedMemoryAndAgrees) {
  check_refit_top_spill<CudaExec>();
}

TEST_F(CudaRefit, TopInOneBlockOfALargeTreeAgrees) {
  check_refit_top_large_tree<CudaExec>();
}

TEST_F(CudaRefit, ZeroesTheCountersItIsHandedOnItsWay) {
  check_refit_counter_reset<CudaExec>();
}

class CudaRestructure : public OnGpu<testing::Test> {};

TEST_F(CudaRestructure, SubtreesAtEveryDepthKeepTheTreeValidAndExact) {
  for (uint32_t depth : {0u, 1u, 4u, 9u}) {
    auto wave = make_generator("cloth-wave", {{"res", 128}, {"frames", 4}});
    check_restructure_subtrees<CudaExec>(*wave, depth);
    auto soup = make_generator("soup", {{"triangles", 50000}, {"distribution", "clustered"},
                                        {"jitter", 1.0}, {"frames", 3}, {"seed", 9}});
    check_restructure_subtrees<CudaExec>(*soup, depth);
  }
  auto same = make_generator("soup", {{"triangles", 1500}, {"distribution", "identical"}, {"frames", 2}});
  check_restructure_subtrees<CudaExec>(*same, 3);
}

class CudaForcedDecisions : public OnGpu<testing::TestWithParam<std::string>> {};

TEST_P(CudaForcedDecisions, EveryBranchOfFormula2IsExact) {
  const ExactFrames scene = exact_frames(*front_scene(GetParam(), 96, 16));
  for (uint32_t cycle : {1u, 2u}) check_forced_decisions("cuda", scene, cycle);
}

INSTANTIATE_TEST_SUITE_P(Scenes, CudaForcedDecisions, testing::ValuesIn(front_scene_names()), front_scene_name);

class CudaRebuildAhead : public OnGpu<testing::TestWithParam<std::string>> {};

TEST_P(CudaRebuildAhead, EveryFrameExactAndTheBuildsAdopted) {
  check_rebuild_ahead("cuda", rebuild_ahead_scene(GetParam(), 96, 16));
}

INSTANTIATE_TEST_SUITE_P(Scenes, CudaRebuildAhead, testing::ValuesIn(rebuild_ahead_scene_names()), front_scene_name);

TEST_F(CudaPipelines, ReplayedPlansRunTheRecordedStepsExactly) {
  check_replayed_plans("cuda", exact_frames(*front_scene("funnel", 96, 16)));
}

// Deformable and rigid objects with declared queries (tests/inter_cases.h): every splitting
// pipeline exact on every frame, the fronts each query keeps, T_R only refitted, and
// pipeline c's forced decisions with cross fronts. Failures name scene, pipeline and frame.
class CudaInter : public OnGpu<testing::TestWithParam<InterCase>> {};

TEST_P(CudaInter, AllPipelinesExactEveryFrame) { check_inter_pipelines("cuda", GetParam()); }

TEST_P(CudaInter, FrontsFollowTheQueriesAndTheRigidTreeOnlyRefits) { check_inter_fronts("cuda", GetParam()); }

INSTANTIATE_TEST_SUITE_P(Scenes, CudaInter, testing::ValuesIn(inter_cases(64, 16)), inter_case_name);

class CudaInterDecisions : public OnGpu<testing::TestWithParam<InterCase>> {};

TEST_P(CudaInterDecisions, EveryBranchOfFormula2IsExact) { check_inter_decisions("cuda", GetParam()); }

INSTANTIATE_TEST_SUITE_P(Scenes, CudaInterDecisions, testing::ValuesIn(inter_decision_cases(96, 16)),
                         inter_case_name);

TEST(CudaInter, ShippedInterScenesExact) {
  if (const auto why = missing_gpu(); !why.empty()) GTEST_SKIP() << why;
  for (const char* name : {"funnel-inter", "sphere-inter", "cloth-ball-inter"}) {
    SCOPED_TRACE(std::string("scene ") + name);
    Scene s = open_scene(name, default_scenes_dir(), {{"frames", 12}});
    check_pipelines_on(config_for("cuda", 0.5, 0.05, 2), *s.source);
  }
}

// The long tests (ctest bvh_cuda_long, label gpu-long; the gpu label runs every other
// test): scenes of millions of triangles, checked against references on the host.

class CudaLong : public OnGpu<testing::Test> {};

TEST_F(CudaLong, LargeUniformSoupRepeatedBuildsAreExact) {
  // Many rebuilds of a 1M-triangle scene: a missing fence in the bottom-up build shows up
  // as an occasional corrupt tree, so repeat.
  auto soup = make_generator("soup", {{"triangles", 1000000}, {"frames", 4}});
  check_pipelines_on(config_for("cuda", 8.0), *soup);
}

// 2^24 + 1 triangles: past the integers a float holds exactly, so an index that goes
// through a float, or a 24-bit field, loses the last one. Pairs of overlapping triangles
// sit in cells 4 apart (2^23 pairs) and the last triangle overlaps the first pair, so the
// exact pair set is known: (2m, 2m + 1) for every m, (0, last) and (1, last). Three frames
// (moving by 1e-3 each) take the front pipelines through generate, a captured and a
// replayed preserve frame; baselines and bvh must agree on every frame.
TEST_F(CudaLong, IndexWidthPastTwoToThe24Triangles) {
  constexpr uint32_t kPairs = 1u << 23, kTriangles = 2 * kPairs + 1, kLast = kTriangles - 1;
  Topology topo;
  topo.faces.resize(kTriangles);
  topo.num_vertices = 3 * kTriangles;
  for (uint32_t t = 0; t < kTriangles; ++t) topo.faces[t] = {3 * t, 3 * t + 1, 3 * t + 2};
  std::vector<vec3f> base(topo.num_vertices);
  auto put = [&](uint32_t t, vec3f c) {
    base[3 * t] = c;
    base[3 * t + 1] = {c.x + 1.0f, c.y, c.z};
    base[3 * t + 2] = {c.x, c.y + 1.0f, c.z + 1.0f};
  };
  for (uint32_t m = 0; m < kPairs; ++m) {
    const vec3f c{4.0f * float(m % 256), 4.0f * float((m / 256) % 256), 4.0f * float(m / 65536)};
    put(2 * m, c);
    put(2 * m + 1, {c.x + 0.5f, c.y + 0.5f, c.z + 0.5f});
  }
  put(kLast, {0.25f, 0.25f, 0.25f});
  std::vector<PrimPair> expected;
  expected.reserve(kPairs + 2);
  for (uint32_t m = 0; m < kPairs; ++m) expected.push_back({2 * m, 2 * m + 1});
  expected.push_back({0, kLast});
  expected.push_back({1, kLast});
  sort_by_pair_key(expected);
  for (const std::string name : {"b", "c", "bvh", "grid", "hash", "sweep"}) {
    PipelineConfig cfg = config_for("cuda", 1.0, 2.0);
    cfg.name = name;
    auto pipeline = make_pipeline(cfg);
    pipeline->set_topology(topo);
    std::vector<vec3f> v(base.size());
    for (uint32_t f = 0; f < 3; ++f) {
      for (size_t k = 0; k < base.size(); ++k) v[k] = {base[k].x + 1e-3f * float(f), base[k].y, base[k].z};
      const FrameStats stats = pipeline->run_frame(v);
      ASSERT_EQ(stats.pairs, expected.size()) << name << " frame " << f;
      const PairSetDiff d = diff_pair_sets(expected, pipeline->sorted_pairs());
      ASSERT_TRUE(d.equal()) << name << " frame " << f << ": " << d.missing_count << " missing, "
                             << d.unexpected_count << " unexpected";
    }
  }
}

}  // namespace cdb::test
