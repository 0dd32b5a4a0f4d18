// The statistics behind `cdbench compare` and the run's noise warning, on synthetic samples
// whose intervals and verdicts are known by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cdbench/core/error.h"
#include "noise_check.h"
#include "run_statistics.h"

namespace cdb {
namespace {

TEST(StudentT, TableAndExpansion) {
  EXPECT_NEAR(student_t95(1), 12.7062, 1e-4);
  EXPECT_NEAR(student_t95(4), 2.7764, 1e-4);
  EXPECT_NEAR(student_t95(30), 2.0423, 1e-4);
  // Beyond the table: the expansion, against published quantiles.
  EXPECT_NEAR(student_t95(40), 2.0211, 2e-4);
  EXPECT_NEAR(student_t95(120), 1.9799, 2e-4);
  EXPECT_TRUE(std::isinf(student_t95(0)));
}

TEST(Metric, MatchesTheSummary) {
  const std::vector<double> v = {4, 1, 3, 2};
  EXPECT_DOUBLE_EQ(metric_of(v, Metric::mean), 2.5);
  EXPECT_DOUBLE_EQ(metric_of(v, Metric::median), 2.5);
  EXPECT_DOUBLE_EQ(metric_of(v, Metric::p95), 4);
  EXPECT_THROW(parse_metric("max"), UsageError);
}

TEST(Estimate, OverRunsIsStudentT) {
  const Estimate e = estimate_over_runs({10, 11, 12});
  EXPECT_EQ(e.basis, CiBasis::repeats);
  EXPECT_EQ(e.n, 3u);
  EXPECT_DOUBLE_EQ(e.value, 11);
  const double half = 4.3027 / std::sqrt(3.0);  // t(2) * sd 1 / sqrt(3)
  EXPECT_NEAR(e.lo, 11 - half, 1e-9);
  EXPECT_NEAR(e.hi, 11 + half, 1e-9);
}

TEST(Estimate, OneRunIsUnbounded) {
  const Estimate e = estimate_over_runs({5});
  EXPECT_TRUE(std::isinf(e.lo) && e.lo < 0);
  EXPECT_TRUE(std::isinf(e.hi) && e.hi > 0);
}

TEST(Estimate, MedianOverFramesByOrderStatistics) {
  std::vector<double> v;
  for (int i = 100; i >= 1; --i) v.push_back(i);  // unsorted on purpose
  const Estimate e = estimate_over_frames(v, Metric::median);
  EXPECT_EQ(e.basis, CiBasis::frames);
  EXPECT_DOUBLE_EQ(e.value, 50.5);
  // n p = 50, 1.96 sqrt(25) = 9.8: ranks floor(40.2) = 40 and ceil(59.8) + 1 = 61.
  EXPECT_DOUBLE_EQ(e.lo, 40);
  EXPECT_DOUBLE_EQ(e.hi, 61);
}

TEST(Estimate, P95OfFewFramesHasNoUpperBound) {
  const Estimate e = estimate_over_frames({1, 2, 3, 4, 5}, Metric::p95);
  EXPECT_DOUBLE_EQ(e.value, 5);
  EXPECT_TRUE(std::isinf(e.hi));
}

TEST(Estimate, PassesBoundFromTheFrameNoise) {
  // Every frame 2 ms with 10% noise over 4 passes: sd of a pass's mean <= 0.2 ms.
  const Estimate e = estimate_over_passes({2, 2, 2}, {0.1, 0.1, 0.1}, 4, Metric::mean);
  EXPECT_EQ(e.basis, CiBasis::passes);
  EXPECT_EQ(e.n, 4u);
  const double half = 3.1824 * 0.2 / 2;
  EXPECT_NEAR(e.lo, 2 - half, 1e-9);
  EXPECT_NEAR(e.hi, 2 + half, 1e-9);
}

Estimate tight(double value) { return estimate_over_runs({value * 0.99, value, value * 1.01}); }

TEST(Verdict, RegressionNeedsThresholdAndNoise) {
  EXPECT_EQ(verdict(tight(10), tight(12), 5), Verdict::regression);
  EXPECT_EQ(verdict(tight(10), tight(8), 5), Verdict::improvement);
  // 3% slower with tight intervals: beyond the noise, under the threshold.
  EXPECT_EQ(verdict(tight(10), tight(10.3), 5), Verdict::unchanged);
  // 20% slower, but the intervals overlap.
  const Estimate wide_a = estimate_over_runs({5, 10, 15}), wide_b = estimate_over_runs({7, 12, 17});
  EXPECT_EQ(verdict(wide_a, wide_b, 5), Verdict::within_noise);
  // One run each: no interval, no verdict either way.
  EXPECT_EQ(verdict(estimate_over_runs({10}), estimate_over_runs({20}), 5), Verdict::unknown);
  EXPECT_NEAR(change_pct(10, 12), 20, 1e-12);
}

FrameStats frame(double ms, const std::string& op, uint32_t repeats = 1, double noise = 0) {
  FrameStats s;
  s.timing.total_ms = ms;
  s.op = op;
  s.timing.repeats = repeats;
  s.timing.total_noise = noise;
  return s;
}

TEST(NoiseCheck, RepeatNoiseAboveTheLimitWarns) {
  const std::vector<FrameStats> quiet = {frame(1, "a", 3, 0.02), frame(1, "a", 3, 0.03), frame(1, "a", 3, 0.02)};
  EXPECT_EQ(noise_warning(measure_noise(quiet, 0)), "");
  const std::vector<FrameStats> noisy = {frame(1, "a", 3, 0.25), frame(1, "a", 3, 0.20), frame(1, "a", 3, 0.30)};
  const std::string w = noise_warning(measure_noise(noisy, 0));
  EXPECT_NE(w.find("25.0%"), std::string::npos) << w;
  EXPECT_NE(w.find("--repeat"), std::string::npos) << w;
}

TEST(NoiseCheck, OnePassCountsOnlyTheCommonOperation) {
  // Steady frames agree; the costly update every third frame is work, not noise.
  std::vector<FrameStats> frames;
  for (int i = 0; i < 9; ++i) frames.push_back(i % 3 == 2 ? frame(5, "update") : frame(1.0 + 0.01 * (i % 2), "refit"));
  EXPECT_EQ(noise_warning(measure_noise(frames, 0)), "");
  // Steady frames that jitter between 1 and 1.5 ms: noise.
  for (size_t i = 0; i < frames.size(); ++i)
    if (frames[i].op == "refit") frames[i].timing.total_ms = (i % 2) ? 1.5 : 1.0;
  const std::string w = noise_warning(measure_noise(frames, 0));
  EXPECT_NE(w.find("'refit' frames"), std::string::npos) << w;
  EXPECT_NE(w.find("--repeat 5"), std::string::npos) << w;
}

TEST(NoiseCheck, OnePassDriftIsNotNoise) {
  // A workload that grows 5% of the first frame each frame (45% over the run, a coefficient
  // of variation of 12%) but never jitters: successive differences see no noise.
  std::vector<FrameStats> drift;
  for (int i = 0; i < 10; ++i) drift.push_back(frame(1.0 + 0.05 * i, "refit"));
  EXPECT_EQ(noise_warning(measure_noise(drift, 0)), "");
  // One outlier among steady frames is not a noisy run either; the median ignores it.
  std::vector<FrameStats> outlier(9, frame(1.0, "refit"));
  outlier[4].timing.total_ms = 3.0;
  EXPECT_EQ(noise_warning(measure_noise(outlier, 0)), "");
}

TEST(Conditions, ABusyHostOrANoiseWarningMakesThemPoor) {
  const HostLoad quiet{0.1, 2}, busy{0.83, 2}, unread{std::nan(""), 2};
  EXPECT_EQ(poor_conditions(quiet, quiet, ""), "");
  EXPECT_EQ(poor_conditions(unread, unread, ""), "") << "an unreadable load is not a busy one";
  EXPECT_EQ(poor_conditions(busy, quiet, ""), "host busy before the run (83%)");
  EXPECT_EQ(poor_conditions(quiet, busy, "noisy run: ..."), "host busy after the measured frames (83%); noise warning");
  EXPECT_EQ(host_load_warning(quiet, "before the run"), "");
  EXPECT_NE(host_load_warning(busy, "after the measured frames").find("busy after the measured frames (83% of its 2"),
            std::string::npos);
}

}  // namespace
}  // namespace cdb
