#pragma once
// The statistics of `cdbench compare`: one run's time as an estimate with a 95% confidence
// interval, and the verdict on two of them. Library-style (no I/O) so tests can feed it
// synthetic samples.
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace cdb {

enum class Metric { mean, median, p95 };
Metric parse_metric(const std::string& name);  // mean | median | p95; throws UsageError
const char* metric_name(Metric m);

// The value of `metric` over per-frame times, as the run summary computes it (stat_of:
// median of an even count is the mean of the middle two, p95 by nearest rank).
double metric_of(const std::vector<double>& frame_ms, Metric m);

// Two-sided 95% quantile of Student's t with `df` degrees of freedom (df >= 1).
double student_t95(size_t df);

// What a confidence interval is over.
enum class CiBasis {
  repeats,  // independent runs of one cell (sweep repeats, or several files): Student t
  passes,   // one run's --repeat passes, from the per-frame noise the file stores (a bound)
  frames,   // one pass: over its measured frames (workload changes widen it)
};
const char* ci_basis_name(CiBasis b);

struct Estimate {
  double value = 0;
  // The 95% interval, of a time, so never below zero: 0 / +inf where the samples cannot
  // bound it (one sample, or too few frames for a p95's order statistics).
  double lo = 0, hi = 0;
  size_t n = 0;  // runs, passes or frames the interval is over
  CiBasis basis = CiBasis::frames;
};

// Independent runs' values (one per run): their mean, mean +- t(n-1) s / sqrt(n).
Estimate estimate_over_runs(const std::vector<double>& run_values);

// One pass's measured frames. mean: Student t over the frames; median and p95: the
// distribution-free order-statistic interval (ranks n p -+ 1.96 sqrt(n p (1 - p)), from the
// binomial's normal approximation).
Estimate estimate_over_frames(const std::vector<double>& frame_ms, Metric m);

// One run of `passes` --repeat passes: frame_ms are the per-frame means over the passes and
// noise their relative standard deviations. The file keeps no per-pass times, so the pass
// metric's standard deviation is bounded by the frames' mean standard deviation (the
// standard deviation of a sum is at most the sum of theirs): sd <= value * sum(noise_f t_f)
// / sum(t_f), and the interval value +- t(passes-1) sd / sqrt(passes) is conservative.
Estimate estimate_over_passes(const std::vector<double>& frame_ms, const std::vector<double>& noise, size_t passes,
                              Metric m);

enum class Verdict {
  unchanged,     // the shift is within the threshold
  within_noise,  // beyond the threshold, but the test does not tell the samples apart
  inconclusive,  // the data cannot decide: poor conditions recorded, or too few samples
  regression,    // B slower: the samples differ (p < kSignificance) and the shift is beyond the threshold
  improvement,   // B faster, likewise
};
const char* verdict_name(Verdict v);

// The two-sided significance level of compare's test.
inline constexpr double kSignificance = 0.05;

// Two-sided p-value of the Mann-Whitney U (Wilcoxon rank-sum) test that a and b come from
// one distribution: exact (the rank sums' distribution counted) without ties and up to 60
// samples in all; else the normal approximation with the tie correction and a continuity
// correction. 1 when either sample is empty.
double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b);

// The smallest two-sided p-value the test can give samples of na and nb (fully separated):
// 2 / C(na + nb, na). Above kSignificance no data can be called different (3 and 3: 0.1).
double mann_whitney_min_p(size_t na, size_t nb);

// The Hodges-Lehmann estimate of B's shift against A: the median of every difference
// b_j - a_i (NaN when a sample is empty).
double hodges_lehmann_shift(const std::vector<double>& a, const std::vector<double>& b);

double median_of(std::vector<double> v);  // NaN when empty

struct Decision {
  Verdict verdict = Verdict::unchanged;
  double p = 1;                       // Mann-Whitney's p-value (NaN when not tested)
  double shift_pct = std::nan("");    // the Hodges-Lehmann shift in percent of A's median
  std::string why;                    // inconclusive: why the data cannot decide
};

// B's samples against A's (one metric value per pass, or per run): inconclusive when a
// sample is not finite (NaN or infinite; no shift then), when `poor`
// (the conditions recorded as poor, its reasons) is not empty or the samples are too few for
// the test to reach kSignificance; else regression or improvement when the test rejects
// equality at kSignificance and the shift exceeds threshold_pct percent; within-noise when
// the shift exceeds it without the test rejecting; unchanged otherwise.
Decision decide(const std::vector<double>& a, const std::vector<double>& b, double threshold_pct,
                const std::string& poor);

// (b - a) / a in percent (NaN when a is 0).
double change_pct(double a, double b);

}  // namespace cdb
