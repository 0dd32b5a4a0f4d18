#include "run_statistics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include "cdbench/core/error.h"
#include "cdbench/pipeline/run_summary.h"

namespace cdb {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kZ95 = 1.959963984540054;  // two-sided 95% normal quantile

double sample_sd(const std::vector<double>& v, double mean) {
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return std::sqrt(ss / double(v.size() - 1));
}

// The 95% interval of a positive time from its half-width on the linear scale, taken on the
// log scale (the delta method: se(log x) = se(x) / x), so that a wide spread never gives a
// negative lower bound: value * exp(-+half / value). For a half-width small against the
// value it is value -+ half to first order. A value that is not positive has no log: the
// linear interval.
std::pair<double, double> positive_interval(double value, double half) {
  if (!(value > 0)) return {value - half, value + half};
  const double factor = std::exp(half / value);
  return {value / factor, value * factor};
}

double mean_of(const std::vector<double>& v) {
  double sum = 0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / double(v.size());
}

}  // namespace

Metric parse_metric(const std::string& name) {
  if (name == "mean") return Metric::mean;
  if (name == "median") return Metric::median;
  if (name == "p95") return Metric::p95;
  fail_usage("--metric " + name + ": expected mean, median or p95");
}

const char* metric_name(Metric m) {
  switch (m) {
    case Metric::mean: return "mean";
    case Metric::median: return "median";
    case Metric::p95: return "p95";
  }
  return "?";
}

double metric_of(const std::vector<double>& frame_ms, Metric m) {
  const Stat s = stat_of(frame_ms);
  if (s.count == 0) return std::nan("");
  return m == Metric::mean ? s.mean : m == Metric::median ? s.median : s.p95;
}

double student_t95(size_t df) {
  // Exact to the digits shown up to 30 degrees of freedom; beyond, the Cornish-Fisher
  // expansion around the normal quantile (error below 1e-5 from 30 on).
  static constexpr std::array<double, 30> table = {
      12.7062, 4.3027, 3.1824, 2.7764, 2.5706, 2.4469, 2.3646, 2.3060, 2.2622, 2.2281,
      2.2010,  2.1788, 2.1604, 2.1448, 2.1314, 2.1199, 2.1098, 2.1009, 2.0930, 2.0860,
      2.0796,  2.0739, 2.0687, 2.0639, 2.0595, 2.0555, 2.0518, 2.0484, 2.0452, 2.0423};
  if (df == 0) return kInf;
  if (df <= table.size()) return table[df - 1];
  const double z = kZ95, n = double(df);
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  return z + (z3 + z) / (4 * n) + (5 * z5 + 16 * z3 + 3 * z) / (96 * n * n) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * n * n * n);
}

const char* ci_basis_name(CiBasis b) {
  switch (b) {
    case CiBasis::repeats: return "repeats";
    case CiBasis::passes: return "passes";
    case CiBasis::frames: return "frames";
  }
  return "?";
}

Estimate estimate_over_runs(const std::vector<double>& run_values) {
  Estimate e;
  e.basis = CiBasis::repeats;
  e.n = run_values.size();
  e.value = mean_of(run_values);
  // Unbounded below a time is bounded by zero.
  if (e.n < 2) {
    e.lo = 0;
    e.hi = kInf;
    return e;
  }
  const double half = student_t95(e.n - 1) * sample_sd(run_values, e.value) / std::sqrt(double(e.n));
  std::tie(e.lo, e.hi) = positive_interval(e.value, half);
  return e;
}

Estimate estimate_over_frames(const std::vector<double>& frame_ms, Metric m) {
  Estimate e;
  e.basis = CiBasis::frames;
  e.n = frame_ms.size();
  e.value = metric_of(frame_ms, m);
  if (m == Metric::mean) {
    const Estimate r = estimate_over_runs(frame_ms);
    e.lo = r.lo;
    e.hi = r.hi;
    return e;
  }
  std::vector<double> v = frame_ms;
  std::sort(v.begin(), v.end());
  const double p = m == Metric::median ? 0.5 : 0.95, n = double(v.size());
  const double spread = kZ95 * std::sqrt(n * p * (1 - p));
  // 1-based ranks of the interval's ends; outside 1..n the samples do not bound it.
  const double lo_rank = std::floor(n * p - spread), hi_rank = std::ceil(n * p + spread) + 1;
  e.lo = lo_rank >= 1 ? v[size_t(lo_rank) - 1] : 0.0;
  e.hi = hi_rank <= n ? v[size_t(hi_rank) - 1] : kInf;
  return e;
}

Estimate estimate_over_passes(const std::vector<double>& frame_ms, const std::vector<double>& noise, size_t passes,
                              Metric m) {
  Estimate e;
  e.basis = CiBasis::passes;
  e.n = passes;
  e.value = metric_of(frame_ms, m);
  double spread = 0, total = 0;
  for (size_t f = 0; f < frame_ms.size() && f < noise.size(); ++f) {
    spread += noise[f] * frame_ms[f];
    total += frame_ms[f];
  }
  if (passes < 2 || total <= 0) {
    e.lo = 0;
    e.hi = kInf;
    return e;
  }
  const double sd = e.value * spread / total;
  const double half = student_t95(passes - 1) * sd / std::sqrt(double(passes));
  std::tie(e.lo, e.hi) = positive_interval(e.value, half);
  return e;
}

const char* verdict_name(Verdict v) {
  switch (v) {
    case Verdict::unchanged: return "unchanged";
    case Verdict::within_noise: return "within-noise";
    case Verdict::inconclusive: return "inconclusive";
    case Verdict::regression: return "REGRESSION";
    case Verdict::improvement: return "improvement";
  }
  return "?";
}

double change_pct(double a, double b) { return a != 0 ? 100.0 * (b - a) / a : std::nan(""); }

double median_of(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mann_whitney_min_p(size_t na, size_t nb) {
  if (na == 0 || nb == 0) return 1.0;
  double ways = 1;  // C(na + nb, na)
  for (size_t k = 1; k <= na; ++k) ways = ways * double(nb + k) / double(k);
  return std::min(1.0, 2.0 / ways);
}

double mann_whitney_p(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t na = a.size(), nb = b.size(), n = na + nb;
  if (na == 0 || nb == 0) return 1.0;
  // Midranks of the pooled samples; ties counted for the variance's correction.
  std::vector<std::pair<double, int>> pooled;
  for (double x : a) pooled.emplace_back(x, 0);
  for (double x : b) pooled.emplace_back(x, 1);
  std::sort(pooled.begin(), pooled.end());
  double rank_sum_a = 0, tie_term = 0;
  bool ties = false;
  for (size_t i = 0; i < n;) {
    size_t j = i;
    while (j < n && pooled[j].first == pooled[i].first) ++j;
    const double rank = 0.5 * double(i + 1 + j);
    for (size_t k = i; k < j; ++k)
      if (pooled[k].second == 0) rank_sum_a += rank;
    const double t = double(j - i);
    tie_term += t * t * t - t;
    ties |= j - i > 1;
    i = j;
  }
  const double u = rank_sum_a - double(na) * double(na + 1) / 2;  // A's U
  if (!ties && n <= 60) {
    // ways[k][s]: subsets of k of the ranks 1..m summing to s, m growing to n; U = s - k(k+1)/2.
    const size_t max_u = na * nb;
    std::vector<std::vector<double>> ways(na + 1, std::vector<double>(max_u + 1, 0.0));
    // Counted directly in U: adding rank m to a subset of k - 1 smaller ranks adds m - k to U.
    ways[0][0] = 1;
    for (size_t m = 1; m <= n; ++m)
      for (size_t k = std::min(na, m); k >= 1; --k) {
        const size_t add = m - k;
        if (add > nb) continue;
        for (size_t s = max_u; s >= add; --s) {
          ways[k][s] += ways[k - 1][s - add];
          if (s == 0) break;
        }
      }
    double total = 0, below = 0, above = 0;
    const size_t observed = size_t(std::llround(u));
    for (size_t s = 0; s <= max_u; ++s) {
      total += ways[na][s];
      if (s <= observed) below += ways[na][s];
      if (s >= observed) above += ways[na][s];
    }
    return std::min(1.0, 2.0 * std::min(below, above) / total);
  }
  const double mean = double(na) * double(nb) / 2;
  const double var = double(na) * double(nb) / 12 * (double(n + 1) - tie_term / (double(n) * double(n - 1)));
  if (!(var > 0)) return 1.0;
  const double z = std::max(0.0, std::fabs(u - mean) - 0.5) / std::sqrt(var);
  return std::min(1.0, std::erfc(z / std::sqrt(2.0)));
}

double hodges_lehmann_shift(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> d;
  d.reserve(a.size() * b.size());
  for (double x : a)
    for (double y : b) d.push_back(y - x);
  return median_of(std::move(d));
}

Decision decide(const std::vector<double>& a, const std::vector<double>& b, double threshold_pct,
                const std::string& poor) {
  Decision d;
  // A NaN or infinite time (a damaged or hand-made file) orders as nothing and shifts by
  // nothing, which would read as `unchanged`: such samples decide nothing.
  const auto not_finite = [](const std::vector<double>& v) {
    return size_t(std::count_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }));
  };
  if (const size_t na = not_finite(a), nb = not_finite(b); na || nb) {
    d.verdict = Verdict::inconclusive;
    d.p = std::nan("");
    d.why = "times that are not finite (NaN or infinite): " + std::to_string(na) + " of " +
            std::to_string(a.size()) + " samples of A, " + std::to_string(nb) + " of " + std::to_string(b.size()) +
            " of B; the files' /frames/t_total_ms hold them";
    return d;
  }
  const double base = median_of(a);
  d.shift_pct = base != 0 ? 100.0 * hodges_lehmann_shift(a, b) / base : std::nan("");
  d.p = std::nan("");
  if (!poor.empty()) {
    d.verdict = Verdict::inconclusive;
    d.why = "poor conditions (" + poor + ")";
    return d;
  }
  if (mann_whitney_min_p(a.size(), b.size()) > kSignificance) {
    d.verdict = Verdict::inconclusive;
    d.why = "too few samples (" + std::to_string(a.size()) + " and " + std::to_string(b.size()) +
            "): the test cannot reach p < 0.05; use --repeat 5 or more";
    return d;
  }
  d.p = mann_whitney_p(a, b);
  const bool beyond = std::fabs(d.shift_pct) > threshold_pct;
  if (!beyond) d.verdict = Verdict::unchanged;
  else if (d.p >= kSignificance) d.verdict = Verdict::within_noise;
  else d.verdict = d.shift_pct > 0 ? Verdict::regression : Verdict::improvement;
  return d;
}

}  // namespace cdb
