// The statistics behind `cdbench compare` and the run's noise warning, on synthetic samples
// whose intervals and verdicts are known by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "harness/measure/noise_check.h"
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
  // t(2) * sd 1 / sqrt(3), on the log scale: 11 * exp(-+half / 11).
  const double half = 4.3027 / std::sqrt(3.0);
  EXPECT_NEAR(e.lo, 11 * std::exp(-half / 11), 1e-3);
  EXPECT_NEAR(e.hi, 11 * std::exp(half / 11), 1e-3);
}

TEST(Estimate, WideSpreadStaysPositive) {
  // Mean 3.7, sd 4.95: the linear interval 3.7 -+ 12.7 * 4.95 / sqrt(2) would reach -40.8.
  const Estimate runs = estimate_over_runs({0.2, 7.2});
  EXPECT_GT(runs.lo, 0);
  EXPECT_GT(runs.hi, runs.value);
  const Estimate times = estimate_over_runs({0.5, 0.6, 9.0});
  EXPECT_GT(times.lo, 0);
  EXPECT_LT(times.lo, 0.5);  // wide: it still covers the smallest time
  // Per-frame noise of 100% over 2 passes: sd <= the value, t(1) 12.7.
  const Estimate passes = estimate_over_passes({2, 2}, {1.0, 1.0}, 2, Metric::mean);
  EXPECT_GT(passes.lo, 0);
  EXPECT_LT(passes.lo, 2);
  // A mean over frames uses the same interval.
  EXPECT_GT(estimate_over_frames({0.5, 0.6, 9.0}, Metric::mean).lo, 0);
}

TEST(Estimate, OneRunIsUnboundedAboveZero) {
  // A time is never negative: what the samples cannot bound below is bounded by zero.
  const Estimate e = estimate_over_runs({5});
  EXPECT_EQ(e.lo, 0);
  EXPECT_TRUE(std::isinf(e.hi) && e.hi > 0);
  const Estimate one_pass = estimate_over_passes({2, 2}, {0.1, 0.1}, 1, Metric::mean);
  EXPECT_EQ(one_pass.lo, 0);
  EXPECT_TRUE(std::isinf(one_pass.hi));
  // Ranks below the first frame: the median of 3 frames is not bounded below by them.
  EXPECT_EQ(estimate_over_frames({1, 2, 3}, Metric::median).lo, 0);
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
  EXPECT_NEAR(e.lo, 2 * std::exp(-half / 2), 1e-3);
  EXPECT_NEAR(e.hi, 2 * std::exp(half / 2), 1e-3);
}

TEST(MannWhitney, ExactSmallSamples) {
  // Fully separated 3 and 3: the two extreme of C(6, 3) = 20 orderings, p = 0.1.
  EXPECT_NEAR(mann_whitney_p({1, 2, 3}, {4, 5, 6}), 0.1, 1e-12);
  EXPECT_NEAR(mann_whitney_min_p(3, 3), 0.1, 1e-12);
  EXPECT_NEAR(mann_whitney_p({1, 2, 3, 4}, {5, 6, 7, 8}), 2.0 / 70, 1e-12);
  EXPECT_NEAR(mann_whitney_p({5, 6, 7, 8}, {1, 2, 3, 4}), 2.0 / 70, 1e-12) << "two-sided";
  // U = 1 of 3 and 3: orderings with U <= 1 are 2 of 20, both tails: 0.2.
  EXPECT_NEAR(mann_whitney_p({1, 2, 4}, {3, 5, 6}), 0.2, 1e-12);
  // Interleaved: no evidence.
  EXPECT_EQ(mann_whitney_p({1, 3, 5, 7}, {2, 4, 6, 8}), mann_whitney_p({2, 4, 6, 8}, {1, 3, 5, 7}));
  EXPECT_GT(mann_whitney_p({1, 3, 5, 7}, {2, 4, 6, 8}), 0.5);
}

TEST(MannWhitney, NormalApproximationWithTies) {
  // 30 against 30, separated, with ties: far below 0.05; identical samples: 1.
  std::vector<double> a, b;
  for (int i = 0; i < 30; ++i) {
    a.push_back(i % 5);
    b.push_back(10 + i % 5);
  }
  EXPECT_LT(mann_whitney_p(a, b), 1e-6);
  EXPECT_NEAR(mann_whitney_p(a, a), 1.0, 1e-12);
}

TEST(MannWhitney, HodgesLehmannShift) {
  EXPECT_DOUBLE_EQ(hodges_lehmann_shift({1, 2, 3}, {11, 12, 13}), 10);
  EXPECT_DOUBLE_EQ(median_of({3, 1, 2, 10}), 2.5);
}

// Deterministic lognormal frame-time samples: median `median`, relative spread `sd`
// (Box-Muller over a fixed 64-bit generator, so the rates below do not depend on the
// standard library's distributions).
struct Samples {
  std::mt19937_64 rng{12345};
  std::vector<double> draw(size_t n, double median, double sd) {
    std::vector<double> v;
    for (size_t i = 0; i < n; ++i) {
      const double u1 = (double(rng() >> 11) + 0.5) / 9007199254740992.0;
      const double u2 = (double(rng() >> 11) + 0.5) / 9007199254740992.0;
      const double z = std::sqrt(-2 * std::log(u1)) * std::cos(6.283185307179586 * u2);
      v.push_back(median * std::exp(sd * z));
    }
    return v;
  }
};

// How often `trials` comparisons of n passes against n passes, B's median `shift` times A's,
// are called a regression or an improvement.
double called_rate(size_t n, double shift, double sd, double threshold, int trials) {
  Samples s;
  int called = 0;
  for (int t = 0; t < trials; ++t) {
    const Decision d = decide(s.draw(n, 1.0, sd), s.draw(n, shift, sd), threshold, "");
    called += d.verdict == Verdict::regression || d.verdict == Verdict::improvement;
  }
  return double(called) / trials;
}

TEST(Decide, IdenticalDistributionsAreCalledDifferentAtMostAtTheSignificance) {
  // docs/usage.md "Comparing runs": at most 5%, the test's level (the exact test is
  // conservative), with or without the threshold on top; the rate is estimated from 4000
  // trials, so allowed three of its standard errors (1 point) above the level.
  const int trials = 4000;
  const double allowed = kSignificance + 3 * std::sqrt(kSignificance * (1 - kSignificance) / trials);
  for (size_t n : {5, 10, 20})
    for (double threshold : {0.0, 5.0})
      EXPECT_LE(called_rate(n, 1.0, 0.10, threshold, trials), allowed) << n << " passes, threshold " << threshold;
}

TEST(Decide, ShiftedDistributionsAreFound) {
  // 20% slower under 5% noise: found almost always with 5 passes each.
  EXPECT_GE(called_rate(5, 1.2, 0.05, 5.0, 2000), 0.95);
  // 10% slower under 10% noise needs more passes: 20 each find it most of the time.
  EXPECT_GE(called_rate(20, 1.1, 0.10, 5.0, 2000), 0.6);
  Samples s;
  const Decision d = decide(s.draw(8, 1.0, 0.02), s.draw(8, 1.5, 0.02), 5.0, "");
  EXPECT_EQ(d.verdict, Verdict::regression);
  EXPECT_NEAR(d.shift_pct, 50, 5);
  EXPECT_LT(d.p, 0.01);
  EXPECT_EQ(decide(s.draw(8, 1.5, 0.02), s.draw(8, 1.0, 0.02), 5.0, "").verdict, Verdict::improvement);
  // Beyond the noise but within the threshold: unchanged.
  EXPECT_EQ(decide(s.draw(8, 1.0, 0.001), s.draw(8, 1.02, 0.001), 5.0, "").verdict, Verdict::unchanged);
  // Beyond the threshold but not told apart from noise.
  EXPECT_EQ(decide({1.0, 1.5, 0.7, 1.3, 0.9}, {1.6, 0.8, 1.4, 1.1, 1.2}, 5.0, "").verdict, Verdict::within_noise);
}

TEST(Decide, TooFewSamplesOrPoorConditionsAreInconclusive) {
  // 3 passes against 3: even fully separated, p >= 0.1.
  const Decision few = decide({1, 1.01, 1.02}, {2, 2.01, 2.02}, 5.0, "");
  EXPECT_EQ(few.verdict, Verdict::inconclusive);
  EXPECT_NE(few.why.find("too few samples (3 and 3)"), std::string::npos) << few.why;
  EXPECT_EQ(decide({1}, {2}, 5.0, "").verdict, Verdict::inconclusive);
  Samples s;
  const Decision busy = decide(s.draw(10, 1.0, 0.01), s.draw(10, 2.0, 0.01), 5.0, "A: host busy before the run (90%)");
  EXPECT_EQ(busy.verdict, Verdict::inconclusive) << "never REGRESSION on a busy host";
  EXPECT_EQ(busy.why, "poor conditions (A: host busy before the run (90%))");
  EXPECT_NEAR(busy.shift_pct, 100, 5) << "the shift is still measured";
}

TEST(Decide, TimesThatAreNotFiniteAreInconclusive) {
  Samples s;
  const std::vector<double> a = s.draw(8, 1.0, 0.01);
  std::vector<double> b = a;
  b[3] = std::nan("");
  const Decision nan = decide(a, b, 5.0, "");
  EXPECT_EQ(nan.verdict, Verdict::inconclusive) << "not unchanged: a NaN is no time";
  EXPECT_NE(nan.why.find("0 of 8 samples of A, 1 of 8 of B"), std::string::npos) << nan.why;
  EXPECT_TRUE(std::isnan(nan.shift_pct));
  const std::vector<double> all_nan(8, std::nan(""));
  EXPECT_EQ(decide(all_nan, all_nan, 5.0, "").verdict, Verdict::inconclusive);
  b[3] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(decide(b, a, 5.0, "").verdict, Verdict::inconclusive);
}

TEST(Verdict, ChangeInPercent) { EXPECT_NEAR(change_pct(10, 12), 20, 1e-12); }

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
