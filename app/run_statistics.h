#pragma once
// The statistics of `cdbench compare`: one run's time as an estimate with a 95% confidence
// interval, and the verdict on two of them. Library-style (no I/O) so tests can feed it
// synthetic samples.
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
  // The 95% interval; -inf / +inf where the samples cannot bound it (one sample, or too
  // few frames for a p95's order statistics).
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
  unchanged,     // |change| within the threshold
  within_noise,  // beyond the threshold, but the intervals overlap
  unknown,       // beyond the threshold, an interval unbounded: the noise is not known
  regression,    // B slower beyond the threshold and the intervals do not overlap
  improvement,   // B faster beyond the threshold and the intervals do not overlap
};
const char* verdict_name(Verdict v);

// B against A: a change counts only when it is both larger than threshold_pct percent of
// A and beyond the noise, i.e. the two 95% intervals do not overlap (stricter than a
// Welch test at 5%: non-overlapping 95% intervals mean p < 0.01 or so).
Verdict verdict(const Estimate& a, const Estimate& b, double threshold_pct);

// (b - a) / a in percent (NaN when a is 0).
double change_pct(double a, double b);

}  // namespace cdb
