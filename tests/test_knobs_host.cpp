#include <limits>

#include "core/outward_rounding.h"
#include "exec/host_exec.h"
#include "inter_cases.h"
#include "knob_cases.h"

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

}  // namespace cdb::test
