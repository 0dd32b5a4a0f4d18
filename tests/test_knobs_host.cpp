#include <limits>
#include <random>

#include "cdbench/core/outward_rounding.h"
#include "cdbench/exec/host_exec.h"
#include "cdbench/geometry/mesh_pieces.h"
#include "cdbench/pipeline/device_mesh.h"
#include "inter_cases.h"
#include "knob_cases.h"
#include "offset_cases.h"
#include "precision_cases.h"

namespace cdb::test {

// The one-ulp cases of the fat-box margin: where rounding to nearest lands inside the real
// lo - M or hi + M (ties to even at 1 +- half an ulp), at subnormals, at 1e30 against
// 1e-30, and at overflow.
TEST(OutwardRounding, OneUlpCases) {
  const float inf = std::numeric_limits<float>::infinity(), max = std::numeric_limits<float>::max();
  EXPECT_EQ(1.0f - 0x1p-25f, 1.0f);  // to nearest: the tie goes back up to 1
  EXPECT_EQ(sub_round_down(1.0f, 0x1p-25f), 1.0f - 0x1p-24f);
  EXPECT_EQ(1.0f + 0x1p-24f, 1.0f);
  EXPECT_EQ(add_round_up(1.0f, 0x1p-24f), 1.0f + 0x1p-23f);
  EXPECT_EQ(sub_round_down(1.0f, 0.25f), 0.75f);  // exact: unchanged
  EXPECT_EQ(add_round_up(1.0f, 0.25f), 1.25f);
  EXPECT_EQ(sub_round_down(1.0f, 0.0f), 1.0f);
  EXPECT_EQ(sub_round_down(0.0f, 0x1p-149f), -0x1p-149f);  // subnormal, exact
  EXPECT_EQ(sub_round_down(0x1p-126f, 0x1p-149f), 0x1p-126f - 0x1p-149f);
  EXPECT_EQ(sub_round_down(1e30f, 1e-30f), std::nextafter(1e30f, 0.0f));
  EXPECT_EQ(add_round_up(1e30f, 1e-30f), std::nextafter(1e30f, inf));
  EXPECT_EQ(add_round_up(-1e30f, 1e-30f), std::nextafter(-1e30f, inf));
  EXPECT_EQ(add_round_up(max, 1.0f), inf);  // above the largest float
  EXPECT_EQ(sub_round_down(-max, 1.0f), -inf);
  EXPECT_EQ(add_round_up(max, max), inf);
  EXPECT_EQ(float_at_or_below(1.0 + 0x1p-30), 1.0f);
  EXPECT_EQ(float_at_or_above(1.0 + 0x1p-30), 1.0f + 0x1p-23f);
  EXPECT_EQ(float_at_or_below(-1.0 - 0x1p-30), -1.0f - 0x1p-23f);
  EXPECT_EQ(float_at_or_above(1e39), inf);
  EXPECT_EQ(float_at_or_below(1e39), max);
  EXPECT_EQ(float_at_or_above(0x1p-160), 0x1p-149f);
  EXPECT_EQ(float_at_or_below(0x1p-160), 0.0f);
}

// Random operands against the FPU's own directed rounding: the same value, not merely a
// bound (a zero result may differ in sign: -0 from the FPU rounding down, +0 here).
TEST(OutwardRounding, MatchesTheFpusDirectedRounding) {
  std::vector<float> a, b;
  random_margin_operands(2000000, a, b);
  for (size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(sub_round_down(a[i], b[i]), fpu_sub_down(a[i], b[i])) << a[i] << " - " << b[i];
    ASSERT_EQ(add_round_up(a[i], b[i]), fpu_add_up(a[i], b[i])) << a[i] << " + " << b[i];
  }
}

TEST(OutwardRounding, SameBitsOnTheExecutor) { check_outward_rounding_on_executor<HostExec>(100000); }

// A grid of unit cells from 0 to 65535: bounds move to the enclosing lines, lines stay.
TEST(BoxGrid, SnapsOutwardOntoTheLines) {
  const BoxGridAxis a = box_grid_axis(0.0f, 65535.0f);
  EXPECT_EQ(a.cell, 1.0);
  EXPECT_EQ(snap_down(a, 0.5f), 0.0f);
  EXPECT_EQ(snap_up(a, 2.25f), 3.0f);
  EXPECT_EQ(snap_down(a, 7.0f), 7.0f);
  EXPECT_EQ(snap_up(a, 7.0f), 7.0f);
  EXPECT_EQ(snap_down(a, 65534.5f), 65534.0f);
  EXPECT_EQ(snap_up(a, 65534.5f), 65535.0f);
  EXPECT_EQ(snap_up(a, 65535.0f), 65535.0f);
  // Quarter cells: 65535 * 0.25 spans [-8192, 8191.75].
  const BoxGridAxis q = box_grid_axis(-8192.0f, 8191.75f);
  EXPECT_EQ(q.cell, 0.25);
  EXPECT_EQ(snap_down(q, -0.1f), -0.25f);
  EXPECT_EQ(snap_up(q, 0.1f), 0.25f);
  // No extent, or no vertices: nothing snaps.
  EXPECT_EQ(box_grid_axis(3.0f, 3.0f).cell, 0.0);
  EXPECT_EQ(snap_down(box_grid_axis(3.0f, 3.0f), 3.0f), 3.0f);
  EXPECT_EQ(box_grid(Aabb<float>::empty()).x.cell, 0.0);
  // A span that overflows float (+-3e38): lines in double, finite, outward.
  const BoxGridAxis w = box_grid_axis(-3e38f, 3e38f);
  EXPECT_TRUE(std::isfinite(w.cell));
  EXPECT_GT(w.cell, 9e33);
  EXPECT_LE(snap_down(w, 1.0f), 1.0f);
  EXPECT_GE(snap_down(w, 1.0f), 1.0f - 1.0001 * w.cell);
  EXPECT_GE(snap_up(w, 1.0f), 1.0f);
  EXPECT_EQ(snap_down(w, -3e38f), -3e38f);
  EXPECT_EQ(snap_up(w, 3e38f), 3e38f);
  // Subnormal cells, finer than the float spacing: a bound between lines goes to the next
  // float outward (more than a cell, less than two float steps), one on a line stays.
  const BoxGridAxis t = box_grid_axis(0.0f, 0x1p-140f);
  EXPECT_EQ(snap_down(t, 0x1p-141f), 0x1p-141f - 0x1p-149f);
  EXPECT_EQ(snap_up(t, 0x1p-141f), 0x1p-141f + 0x1p-149f);
  EXPECT_EQ(snap_down(t, 0x1p-140f), 0x1p-140f);
}

// Over [0, 1] line k is the real k / 65535, never a float for 0 < k < 65535 (65535 is odd),
// and x * 65535 is exact in double: each snapped bound must be the float just outside its
// line (the line rounded outward), for random x.
TEST(BoxGrid, SnapsToTheFloatJustOutsideEachLine) {
  const BoxGridAxis a = box_grid_axis(0.0f, 1.0f);
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) {
    const float x = unit(rng);
    const double k = std::floor(double(x) * 65535.0);
    if (k == 0.0 || k * (1.0 / 65535.0) == x) continue;
    const double below = k / 65535.0, above = (k + 1.0) / 65535.0;
    const float lo = snap_down(a, x), hi = snap_up(a, x);
    ASSERT_LE(double(lo), below) << x;
    ASSERT_GT(double(std::nextafter(lo, 2.0f)), below) << x;
    if (k + 1.0 < 65535.0) {
      ASSERT_GE(double(hi), above) << x;
      ASSERT_LT(double(std::nextafter(hi, -1.0f)), above) << x;
    }
  }
}

class HostPrecision : public testing::TestWithParam<BaselineCase> {};

TEST_P(HostPrecision, Q16BoxesContainTheExactOnesWithinOneCell) { check_q16_boxes(GetParam().make()); }

TEST_P(HostPrecision, FloatBoxesContainTheDoubleBoxes) {
  const SceneFrames s = GetParam().make();
  for (float margin : precision_margins(s))
    for (BoxPrecision precision : {BoxPrecision::fp32, BoxPrecision::q16}) {
      check_contains_double_boxes(s, margin, precision);
      if (testing::Test::HasFatalFailure()) return;
    }
}

TEST_P(HostPrecision, ExecutorGridEqualsTheHostGrid) {
  const SceneFrames s = GetParam().make();
  check_executor_grid<HostExec>(s, false);
  check_executor_grid<HostExec>(s, true);
}

TEST_P(HostPrecision, EveryPipelineReportsExactlyTheQ16Overlaps) {
  size_t extra = 0;
  check_q16_pipelines("cpu", GetParam().make(), extra);
}

INSTANTIATE_TEST_SUITE_P(Scenes, HostPrecision, testing::ValuesIn(precision_cases()), baseline_case_name);

class HostOffsets : public testing::TestWithParam<OffsetCase> {};

TEST_P(HostOffsets, Fp64KeepsEveryPairOfTheDoubleGeometry) { check_fp64_offset("cpu", GetParam().offset); }
TEST_P(HostOffsets, Fp32KeepsEveryPairButBlursAndWarns) { check_fp32_offset("cpu", GetParam().offset); }

INSTANTIATE_TEST_SUITE_P(Sheets, HostOffsets, testing::ValuesIn(offset_cases()), offset_case_name);

TEST(PositionRounding, Fp64RebasesOnTheFirstFramesCentreUntilRestarted) {
  const auto sheet = millimetre_sheet(1e7);
  EXPECT_TRUE(float_spacing_warning(*millimetre_sheet(0.0), 0, false).empty());
  std::vector<vec3d> a, b;
  sheet->positions(0, a);
  sheet->positions(2, b);
  PositionRounding fp64(true), fp32(false);
  std::vector<vec3f> out;
  fp64.round(a, out);
  const vec3d origin = fp64.origin();
  EXPECT_NEAR(origin.x, 1e7, 1.0);
  for (size_t v = 0; v < a.size(); ++v) {
    EXPECT_EQ(out[v].x, float(a[v].x - origin.x));
    EXPECT_LT(std::fabs(out[v].z), 1.0f);
  }
  fp64.round(b, out);
  EXPECT_EQ(fp64.origin().x, origin.x) << "the origin stays for the run";
  fp64.restart();
  fp64.round(b, out);
  EXPECT_EQ(fp64.origin().x, bounds_centre(b).x);
  fp32.round(a, out);
  EXPECT_EQ(fp32.origin().x, 0.0);
  EXPECT_EQ(out[0].x, float(a[0].x));
  // Beyond float range: an error naming the vertex and the remedy; fp64 takes it.
  std::vector<vec3d> far = {{1e39, 0, 0}, {1e39, 1, 0}, {1e39, 0, 1}};
  EXPECT_THROW(fp32.round(far, out), Error);
  PositionRounding rebased(true);
  EXPECT_NO_THROW(rebased.round(far, out));
}

// Coarse cells (a 1e6-wide scene of 1e-3 cubes) add pairs; with swept boxes and a margin
// on a fast soup, the grid spans the previous frame too and the margin goes on the snapped box.
TEST(HostKnobs, Q16AddsPairsAndCombinesWithMarginAndSweptBoxes) {
  size_t coarse = 0, swept = 0;
  check_q16_pipelines("cpu", with_point_at(cube_lattice(3, 1e-3f), 1e6f), coarse);
  EXPECT_GT(coarse, 0u);
  auto soup = fast_soup(4);
  check_q16_pipelines("cpu", frames_of(*soup), swept, 0.1f * mean_box_extent(*soup), true);
  EXPECT_GT(swept, 0u);
}

TEST(HostKnobs, MarginGivesExactlyTheInflatedBoxPairs) {
  auto soup = fast_soup(5);
  check_margin("cpu", *soup, 0.25f * mean_box_extent(*soup));
  auto cloth = rolling_cloth(5);
  check_margin("cpu", *cloth, 0.5f * mean_box_extent(*cloth));
}

TEST(HostKnobs, SweptGivesExactlyTheSweptBoxPairs) {
  auto soup = fast_soup(5);
  check_swept("cpu", *soup);
  auto cloth = rolling_cloth(5);
  check_swept("cpu", *cloth);
}

TEST(HostKnobs, LazyRefitKeepsTheLastRefitsBoxesAndMissesPairs) {
  auto soup = fast_soup(7);
  check_lazy_refit("cpu", *soup, 3);
}

// A scene split into a deformable and a rigid tree (declared queries): both trees keep
// their last refit's boxes between refits, so the pairs are exactly the stale boxes'
// overlaps among the pairs the scene asks for, and the teleporting rigid bodies are missed.
TEST(HostKnobs, LazyRefitOnSplitTreesKeepsBothTreesStale) {
  StoredFrames scene(with_queries(jumping_rigid_bodies(7, false), {"soup"}, {{"soup", "tri"}, {"soup", "box"}}));
  check_lazy_refit("cpu", scene, 3);
}

TEST(HostKnobs, UntimedPhasesKeepEveryPipelineExact) { check_launch_knobs("cpu", false, false); }

TEST(HostKnobs, PieceOrderedBuildsKeepEveryPipelineExact) { check_build_pieces("cpu"); }

// --build-pieces: auto orders the falling bodies (43 pieces of 80 or 64 faces) and not a soup
// (every face a piece), on orders both; off and a cloth (one piece) neither.
TEST(HostKnobs, BuildPiecesAutoTakesObjectsNotASoup) {
  HostExec exec;
  DeviceMesh<HostExec> mesh(exec);
  const auto bodies = make_generator("n-body", {{"spheres", 40}, {"cones", 3}, {"sphere_level", 1}, {"frames", 1}});
  const auto soup = make_generator("soup", {{"triangles", 1200}, {"frames", 1}});
  const auto cloth = make_generator("cloth-wave", {{"res", 16}, {"frames", 1}});
  const auto ordered = [&](const FrameSource& source, AutoSwitch choice) {
    mesh.set_topology(exec, source.topology(), SplitRule::rigid);
    mesh.set_pieces(exec, source.topology(), choice, MortonBits::b63);
    return mesh.pieces().on();
  };
  EXPECT_TRUE(ordered(*bodies, AutoSwitch::automatic));
  EXPECT_FALSE(ordered(*soup, AutoSwitch::automatic));
  EXPECT_TRUE(ordered(*soup, AutoSwitch::on));
  EXPECT_FALSE(ordered(*bodies, AutoSwitch::off));
  EXPECT_FALSE(ordered(*cloth, AutoSwitch::on));
}

// Faces sharing a vertex are one piece, numbered by first face; a face with a vertex out of
// range is its own; a subset numbers its own positions.
TEST(MeshPieces, ConnectedFacesShareAPiece) {
  const std::vector<Tri> faces = {{0, 1, 2}, {5, 6, 7}, {2, 3, 4}, {8, 9, 99}, {7, 8, 9}};
  const MeshPieces all = mesh_pieces(faces, 10, {});
  EXPECT_EQ(all.leaf_piece, (std::vector<uint32_t>{0, 1, 0, 2, 1}));
  EXPECT_EQ(all.piece_first, (std::vector<uint32_t>{0, 1, 3}));
  const MeshPieces some = mesh_pieces(faces, 10, {4, 2, 0});
  EXPECT_EQ(some.leaf_piece, (std::vector<uint32_t>{0, 1, 1}));
  EXPECT_EQ(some.piece_first, (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(mesh_pieces({}, 0, {}).count(), 0u);
  EXPECT_EQ(piece_bits(0), 0u);
  EXPECT_EQ(piece_bits(1), 0u);
  EXPECT_EQ(piece_bits(2), 1u);
  EXPECT_EQ(piece_bits(3), 2u);
  EXPECT_EQ(piece_bits(4096), 12u);
  EXPECT_EQ(piece_bits(4097), 13u);
  EXPECT_TRUE(piece_order_fits(MortonBits::b63, kMaxPieceBits));
  EXPECT_TRUE(piece_order_fits(MortonBits::b30, kMaxPieceBits));
}

TEST(HostKnobs, UpdateVariantsKeepEveryPipelineExact) { check_update_knobs("cpu"); }

TEST(HostKnobs, ProbedUpdatesRunOnce) { check_update_probe("cpu"); }

TEST(HostKnobs, ProbeCountsBoundTheUpdate) { check_probe_counts("cpu"); }

TEST(HostKnobs, PairBufferGrowsBetweenFrames) { check_pairs_grown_ahead("cpu"); }

}  // namespace cdb::test
