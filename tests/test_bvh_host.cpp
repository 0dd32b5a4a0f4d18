#include <vector>

#include "baseline_cases.h"
#include "bvh_cases.h"
#include "cell_cases.h"
#include "scenes/load/scene.h"
#include "cdbench/core/error.h"
#include "cdbench/exec/host_exec.h"
#include "cdbench/front/operations.h"
#include "cdbench/front/warp_traversal.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

class HostSoup : public testing::TestWithParam<SoupCase> {};

TEST_P(HostSoup, TreeValidAndPairsExact) { check_soup_case<HostExec>(GetParam()); }

TEST_P(HostSoup, RadixOrderGivesTheHistogramOrder) { check_radix_order_matches<HostExec>(GetParam()); }

// Piece ordered builds: falling spheres and cones (each its own piece), a soup (every
// triangle one, 1200), and the funnel (its cloth and its funnel), in 63- and 30-bit keys.
TEST(HostPieces, EachPieceSpansOneSubtree) {
  for (MortonBits bits : {MortonBits::b63, MortonBits::b30}) {
    EXPECT_EQ(check_piece_order<HostExec>(*make_generator("n-body", {{"spheres", 40}, {"cones", 3}, {"sphere_level", 1},
                                                                {"frames", 6}, {"warmup", 0}}),
                                     bits), 43u);
    EXPECT_EQ(check_piece_order<HostExec>(*make_generator("soup", {{"triangles", 1200}, {"frames", 2}, {"seed", 3}}), bits),
              1200u);
    EXPECT_GE(check_piece_order<HostExec>(*make_generator("funnel", {{"res", 20}, {"frames", 6}}), bits), 2u);
  }
}

INSTANTIATE_TEST_SUITE_P(Soups, HostSoup, testing::ValuesIn(soup_cases()), case_name);

// Two front nodes a preserve thread (PreserveTwoNodesFn): its launch's threads take every
// front node exactly once, each block's two halves coalesced, for any front size.
TEST(PreserveTwoNodes, ThreadsTakeEveryFrontNodeOnce) {
  using Two = PreserveTwoNodesFn<PreserveFrontFn<false>>;
  for (uint32_t n : {0u, 1u, 255u, 256u, 257u, 511u, 512u, 513u, 1000u, 5121u}) {
    const uint64_t threads = Two::threads_for(n);
    EXPECT_EQ(threads % kStagedThreads, 0u) << n;
    EXPECT_LT(2 * threads, uint64_t(n) + 2 * kStagedThreads + 1) << n;
    std::vector<int> taken(n, 0);
    for (uint32_t e = 0; e < threads; ++e) {
      const uint32_t first = Two::first_node(e);
      EXPECT_EQ(first % (2 * kStagedThreads), e % kStagedThreads) << n << " thread " << e;
      for (uint32_t node : {first, first + kStagedThreads})
        if (node < n) ++taken[node];
    }
    for (uint32_t k = 0; k < n; ++k) ASSERT_EQ(taken[k], 1) << n << " node " << k;
  }
}

class HostBaselines : public testing::TestWithParam<BaselineCase> {};

TEST_P(HostBaselines, SweepHashAndGridExact) { check_baselines<HostExec>(GetParam().make()); }

INSTANTIATE_TEST_SUITE_P(Scenes, HostBaselines, testing::ValuesIn(baseline_cases()),
                         baseline_case_name);

// Spread launches (front/warp_traversal.h): the largest spread up to a warp whose launch
// stays within the resident threads, and exactly one starting thread per traversal.
TEST(SpreadLaunch, FillsTheResidentThreadsAndStartsEachTraversalOnce) {
  EXPECT_EQ(spread_shift_for(9218, 270336, 1), 4u);
  EXPECT_EQ(spread_shift_for(48000, 270336, 1), 2u);
  EXPECT_EQ(spread_shift_for(135168, 270336, 1), 1u);
  EXPECT_EQ(spread_shift_for(135169, 270336, 1), 0u);
  EXPECT_EQ(spread_shift_for(297083, 270336, 4), 1u);
  EXPECT_EQ(spread_shift_for(5000000, 270336, 4), 0u);
  EXPECT_EQ(spread_shift_for(1, 270336, 1), kMaxSpreadShift);
  EXPECT_EQ(spread_shift_for(0, 270336, 1), kMaxSpreadShift);
  EXPECT_EQ(spread_shift_for(7, 2, 1), 0u);
  for (uint32_t shift = 0; shift <= kMaxSpreadShift; ++shift) {
    const uint32_t traversals = 37;
    std::vector<int> started(traversals, 0);
    for (uint32_t e = 0; e < (traversals << shift); ++e) {
      uint32_t index = ~0u;
      if (spread_start(e, shift, index)) {
        ASSERT_LT(index, traversals);
        ++started[index];
      }
    }
    for (uint32_t i = 0; i < traversals; ++i) EXPECT_EQ(started[i], 1) << "shift " << shift << " traversal " << i;
  }
}

TEST(HostCells, CoordinateMonotoneAtExtremes) { check_cell_coord_monotone_at_extremes<HostExec>(); }

TEST(HostCells, BoxRangesHoldTheirPointsAndHomeCells) {
  check_box_ranges_hold_their_points_and_homes<HostExec>();
}

TEST(HostCells, OnePointSceneIsOneCell) { check_one_point_scene_is_one_cell<HostExec>(); }

TEST(HostCells, SceneStatsReduction) { check_scene_stats_reduction<HostExec>(); }

TEST(HostHashBaseline, FewLargeBoxesAreTestedDirectlyManyCoarsenTheGrid) {
  EXPECT_EQ(check_baselines<HostExec>(soup_with_giants(3000, 10, false)).hash_regrids, 0u);
  EXPECT_GT(check_baselines<HostExec>(soup_with_giants(3000, 100, false)).hash_regrids, 0u);
}

// Boxes at float's limit, and grown past it by a margin to +-inf (outward rounding): the
// cells come from their finite bounds, so grid and hash stay exact.
TEST(HostCellBaselines, ExactAtFloatLimitAndPastItToInfinity) {
  check_baselines<HostExec>(float_limit_boxes(300, 3));
  check_baselines<HostExec>(float_limit_boxes(300, 3), false, 1e38f);
  check_baselines<HostExec>(float_limit_boxes(300, 3), true, 1e37f);
}

TEST(HostHashBaseline, SecondPassSortsTheEntriesTheFirstGrewTo) { check_hash_second_pass<HostExec>(bimodal_soup(3000, 0.05f, 7)); }

// The grid plans its sort from the last frame: steady frames fit the plan; a plan far too
// small (1024 entries, 1 key bit) makes each frame re-run once, exactly, never truncate.
TEST(HostGridBaseline, PlanFromTheLastFrameReRunsWhenShort) {
  auto soup = [] {
    return frames_of(*make_generator("soup", {{"triangles", 20000}, {"frames", 4}, {"seed", 9}}));
  };
  EXPECT_EQ(check_baselines<HostExec>(soup()).grid_reruns, 0u);
  EXPECT_EQ(check_baselines<HostExec>(soup(), true).grid_reruns, 4u);
  EXPECT_EQ(check_baselines<HostExec>(multiscale_soup(5000, 4), true).grid_reruns, 2u);
}

// A scene-spanning triangle goes to a coarse level in a few cells, the small ones to the
// finest levels; no box covers more than kGridMaxCellsPerBox cells, however wide.
TEST(HostGridBaseline, WideBoxesGoToCoarserLevelsInFewCells) {
  for (bool far : {false, true}) {
    const GridPlacement p = grid_placement<HostExec>(soup_with_giants(3000, 1, far));
    const uint32_t small = *std::max_element(p.level.begin(), p.level.end() - 1);
    EXPECT_LE(small, 1u) << far;
    EXPECT_GE(p.level.back(), small + 2) << far;
    for (uint32_t c : p.cells) ASSERT_LE(c, kGridMaxCellsPerBox) << far;
  }
  const GridPlacement m = grid_placement<HostExec>(multiscale_soup(5000, 3));
  EXPECT_GE(*std::max_element(m.level.begin(), m.level.end()), 2u);
  for (uint32_t c : m.cells) ASSERT_LE(c, kGridMaxCellsPerBox);
}

// Through the pipeline: a frame whose entries outgrow the plan made from the last frame is
// re-run (op regrid) and exact; the next frame plans from it and runs once.
TEST(HostGridBaseline, PipelineReRunsAFrameThatOutgrowsItsPlan) {
  const std::vector<std::string> ops = grid_pipeline_ops("cpu", straddling_pairs(10));
  EXPECT_EQ(ops, (std::vector<std::string>{"grid", "regrid", "grid"}));
}

TEST(HostPipelines, ExactOnClothAndFunnelWithGrowingPairBuffer) {
  auto wave = make_generator("cloth-wave", {{"res", 24}, {"frames", 6}});
  check_pipelines_on(config_for("cpu", 0.01), *wave);
  auto funnel = make_generator("funnel", {{"res", 20}, {"frames", 6}, {"segments", 16}, {"ball_level", 1}});
  check_pipelines_on(config_for("cpu", 8.0), *funnel);
}

// Every front operation sequence: update every frame (cycle 1), alternating (2), longer
// cycles (3, 5: periodic's generate-instead-of-update) and the adaptive rule (0: auto,
// whose schedule follows measured times); fronts that start far too
// small so they must grow while sprouting. Each scene and its oracle pairs are made once,
// for every cycle.
class HostFrontCycles : public testing::TestWithParam<std::string> {};

TEST_P(HostFrontCycles, AllPipelinesExactEveryFrame) { check_front_cycles("cpu", GetParam(), 24, 12); }

INSTANTIATE_TEST_SUITE_P(Scenes, HostFrontCycles, testing::ValuesIn(front_scene_names()), front_scene_name);

TEST(HostFrontPipelines, RecordTheOperationsOfTheirCycle) {
  auto wave = make_generator("cloth-wave", {{"res", 16}, {"frames", 9}});
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected_ops = {
      {"a", {"build+generate", "refit+preserve", "refit+update", "refit+preserve", "refit+update"}},
      {"periodic", {"build+generate", "refit+preserve", "refit+update", "refit+preserve", "refit+generate"}},
      {"reference", {"build+generate", "build+generate", "build+generate", "build+generate", "build+generate"}},
      {"a in place", {"build+generate", "refit+preserve", "refit+update-in-place", "refit+preserve",
                      "refit+update-in-place"}},
  };
  for (const auto& [label, ops] : expected_ops) {
    const std::string name = label.substr(0, label.find(' '));
    PipelineConfig cfg = config_for("cpu", 8.0, 8.0, 2);
    cfg.name = name;
    cfg.fronts.update_in_place = label != name;
    auto p = make_pipeline(cfg);
    p->set_topology(wave->topology());
    std::vector<vec3f> v;
    for (uint32_t f = 0; f < ops.size(); ++f) {
      wave->frame(f, v);
      const FrameStats s = p->run_frame(v);
      EXPECT_EQ(s.op, ops[f]) << name << " frame " << f;
      EXPECT_GT(s.fronts.internal + s.fronts.external, 0u) << name;
      if (name != "unordered") {
        EXPECT_GT(s.quality.q_root, 0.0) << name;
      }
    }
  }
}

// The frame loop's one synchronization (the counters' read-back) is the design's promise;
// the host executor counts read-backs the way the CUDA one counts stream waits. Buffers are
// generous so no frame grows; each growth would add one read-back per re-run.
TEST(HostPipelines, OneSynchronizationPerFrame) {
  auto wave = make_generator("cloth-wave", {{"res", 16}, {"frames", 7}});
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = config_for("cpu", 64.0, 64.0, 2);
    cfg.name = name;
    auto p = make_pipeline(cfg);
    p->set_topology(wave->topology());
    std::vector<vec3f> v;
    for (uint32_t f = 0; f < 7; ++f) {
      wave->frame(f, v);
      const FrameStats s = p->run_frame(v);
      EXPECT_EQ(s.timing.query_reruns, 0u) << name << " frame " << f;
      // hash reads its cell-entry totals back to size the entry sort; the radix-sort
      // baseline reads the produced front sizes before sorting them.
      const bool produced_front =
          s.op.find("preserve") == std::string::npos && s.op.find("in-place") == std::string::npos;
      const uint32_t expected = name == "hash" || (name == "radix-order" && produced_front) ? 2 : 1;
      EXPECT_EQ(s.timing.host_syncs, expected) << name << " frame " << f << " " << s.op;
    }
  }
}

// --rebuild-ahead: the ahead frame launches its build without waiting for it; the frame that
// adopts it waits for the side stream and reads its fronts' sizes back, two more.
TEST(HostPipelines, BuildsAheadSynchronizeOnlyWhereAdopted) {
  auto wave = make_generator("cloth-wave", {{"res", 16}, {"frames", 9}});
  for (const char* name : {"a", "b", "c"}) {
    PipelineConfig cfg = config_for("cpu", 64.0, 64.0, 2);
    cfg.name = name;
    cfg.tree.rebuild_ahead = AutoSwitch::on;
    cfg.tree.rebuild_every = 3;
    auto p = make_pipeline(cfg);
    p->set_topology(wave->topology());
    std::vector<vec3f> v;
    uint32_t adopted = 0;
    for (uint32_t f = 0; f < 9; ++f) {
      wave->frame(f, v);
      const FrameStats s = p->run_frame(v);
      ASSERT_TRUE(s.plan.has_value());
      const bool adopts = s.plan->trees == TreeStep::adopt;
      adopted += adopts;
      EXPECT_EQ(s.timing.host_syncs, adopts ? 3u : 1u) << name << " frame " << f << " " << s.op;
      EXPECT_EQ(s.timing.ahead_ms > 0.0, adopts) << name << " frame " << f;
    }
    EXPECT_EQ(adopted, 2u) << name;  // built ahead at frames 3 and 6, adopted at 4 and 7
  }
}

TEST(HostPipelines, SecondPassAfterGrowthMatchesTheFirst) {
  auto funnel = make_generator("funnel", {{"res", 20}, {"frames", 6}, {"segments", 16}, {"ball_level", 1}});
  check_second_pass_matches_first(config_for("cpu", 0.01, 0.05, 2), *funnel);
}

TEST(HostRefit, TopInOneBlockSpillsPastSharedMemoryAndAgrees) { check_refit_top_spill<HostExec>(); }
TEST(HostRefit, TopInOneBlockOfALargeTreeAgrees) { check_refit_top_large_tree<HostExec>(); }
TEST(HostRefit, ZeroesTheCountersItIsHandedOnItsWay) { check_refit_counter_reset<HostExec>(); }

TEST(HostRestructure, SubtreesAtEveryDepthKeepTheTreeValidAndExact) {
  for (uint32_t depth : {0u, 1u, 3u, 6u}) {
    auto wave = make_generator("cloth-wave", {{"res", 24}, {"frames", 4}});
    check_restructure_subtrees<HostExec>(*wave, depth);
    auto soup = make_generator("soup", {{"triangles", 2000}, {"distribution", "clustered"},
                                        {"jitter", 3.0}, {"frames", 3}, {"seed", 9}});
    check_restructure_subtrees<HostExec>(*soup, depth);
  }
  auto same = make_generator("soup", {{"triangles", 300}, {"distribution", "identical"}, {"frames", 2}});
  check_restructure_subtrees<HostExec>(*same, 2);
}

class HostForcedDecisions : public testing::TestWithParam<std::string> {};

TEST_P(HostForcedDecisions, EveryBranchOfFormula2IsExact) {
  const ExactFrames scene = exact_frames(*front_scene(GetParam(), 24, 8));
  for (uint32_t cycle : {1u, 2u}) check_forced_decisions("cpu", scene, cycle);
}

INSTANTIATE_TEST_SUITE_P(Scenes, HostForcedDecisions, testing::ValuesIn(front_scene_names()), front_scene_name);

class HostRebuildAhead : public testing::TestWithParam<std::string> {};

TEST_P(HostRebuildAhead, EveryFrameExactAndTheBuildsAdopted) {
  check_rebuild_ahead("cpu", rebuild_ahead_scene(GetParam(), 24, 9));
}

INSTANTIATE_TEST_SUITE_P(Scenes, HostRebuildAhead, testing::ValuesIn(rebuild_ahead_scene_names()), front_scene_name);

TEST(HostPipelines, ReplayedPlansRunTheRecordedStepsExactly) {
  check_replayed_plans("cpu", exact_frames(*front_scene("funnel", 24, 8)));
}

TEST(HostPipelines, DeclaredQueriesReportOnlyWhatTheSceneAsks) {
  Scene s = open_scene("funnel-inter", default_scenes_dir(), {{"res", 16}, {"frames", 4}, {"segments", 16}, {"ball_level", 1}});
  check_declared_queries("cpu", *s.source);
}

TEST(HostPipelines, SkipAdjacentMatchesTheFilteredOracle) {
  auto wave = make_generator("cloth-wave", {{"res", 24}, {"frames", 6}});
  check_skip_adjacent("cpu", *wave);
  auto funnel = make_generator("funnel", {{"res", 16}, {"frames", 4}, {"segments", 16}, {"ball_level", 1}});
  check_skip_adjacent("cpu", *funnel);
}

TEST(HostPipelines, PairBufferGrowthIsCountedNotTruncated) {
  auto soup = make_generator("soup", {{"triangles", 500}, {"distribution", "identical"}});
  PipelineConfig cfg;
  cfg.device = "cpu";
  cfg.capacity.pairs_per_triangle = 0.0;
  auto p = make_pipeline(cfg);
  p->set_topology(soup->topology());
  std::vector<vec3f> v;
  soup->frame(0, v);
  const FrameStats s = p->run_frame(v);
  EXPECT_EQ(s.pairs, 500ull * 499 / 2);
  EXPECT_GE(s.timing.query_reruns, 1u);
  EXPECT_GE(p->memory().growths, 1u);
  EXPECT_EQ(p->sorted_pairs().size(), 500ull * 499 / 2);
}

class HostExtremes : public testing::TestWithParam<BaselineCase> {};

TEST_P(HostExtremes, EveryPipelineExactEveryFrame) {
  StoredFrames scene(GetParam().make());
  check_pipelines_on(config_for("cpu", 0.5, 0.05, 1), scene);
}

INSTANTIATE_TEST_SUITE_P(Scenes, HostExtremes, testing::ValuesIn(extreme_cases()), baseline_case_name);

TEST(PairAccuracy, CountsMissesFalsePositivesAndDuplicates) {
  const std::vector<PrimPair> oracle = {{0, 1}, {0, 2}, {1, 2}, {2, 3}};
  const PairAccuracy same = pair_accuracy(oracle, oracle);
  EXPECT_EQ(same.recall, 1.0);
  EXPECT_EQ(same.precision, 1.0);
  const PairAccuracy a = pair_accuracy(oracle, {{0, 1}, {0, 2}, {0, 2}, {1, 3}, {2, 3}});
  EXPECT_EQ(a.missed, 1u);           // (1, 2)
  EXPECT_EQ(a.false_positives, 2u);  // the second (0, 2) and (1, 3)
  EXPECT_DOUBLE_EQ(a.recall, 3.0 / 4.0);
  EXPECT_DOUBLE_EQ(a.precision, 3.0 / 5.0);
  EXPECT_EQ(pair_accuracy({}, {}).recall, 1.0);
  EXPECT_EQ(pair_accuracy(oracle, {}).recall, 0.0);
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
