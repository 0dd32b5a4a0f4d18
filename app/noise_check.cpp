#include "noise_check.h"

#include <cmath>
#include <cstdio>
#include <map>

#include "pipeline/run_summary.h"

namespace cdb {

NoiseMeasure measure_noise(const std::vector<FrameStats>& frames, uint32_t warmup) {
  NoiseMeasure m;
  if (frames.empty()) return m;
  const RunSummary r = summarize_run(frames, warmup);
  m.passes = r.repeats;
  if (r.repeats > 1) {
    m.cv = r.noise_median;
    m.frames = r.total.count;
    return m;
  }
  std::map<std::string, size_t> ops;
  for (size_t f = r.warmup; f < frames.size(); ++f) ++ops[frames[f].op];
  size_t most = 0;
  for (const auto& [op, count] : ops)
    if (count > most) {
      most = count;
      m.op = op;
    }
  std::vector<double> t;
  for (size_t f = r.warmup; f < frames.size(); ++f)
    if (frames[f].op == m.op) t.push_back(frames[f].total_ms);
  m.frames = t.size();
  if (t.size() < 2) return m;
  double mean = 0, ss = 0;
  for (double x : t) mean += x;
  mean /= double(t.size());
  for (double x : t) ss += (x - mean) * (x - mean);
  m.cv = mean > 0 ? std::sqrt(ss / double(t.size() - 1)) / mean : 0.0;
  return m;
}

std::string noise_warning(const NoiseMeasure& m) {
  if (m.frames < 2 || !(m.cv > kNoiseWarningLimit)) return "";
  char text[512];
  if (m.passes > 1)
    std::snprintf(text, sizeof text,
                  "noisy run: the passes' times differ by %.1f%% (median over %zu frames of the relative std. dev. "
                  "over %u passes), above %.0f%%; use more --repeat passes or a quieter machine",
                  100.0 * m.cv, m.frames, m.passes, 100.0 * kNoiseWarningLimit);
  else
    std::snprintf(text, sizeof text,
                  "noisy run: frame times vary by %.1f%% (coefficient of variation over the %zu measured '%s' frames "
                  "of one pass, workload changes included), above %.0f%%; measure the noise with --repeat 5, or run "
                  "on a quieter machine",
                  100.0 * m.cv, m.frames, m.op.c_str(), 100.0 * kNoiseWarningLimit);
  return text;
}

}  // namespace cdb
