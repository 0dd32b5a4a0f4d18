#include "noise_check.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <map>

#include <unistd.h>

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
  if (t.size() < 3) return m;
  // One pass holds no repeat of a frame, and the workload drifts over a scene (pairs grow,
  // fronts go stale): the spread of the frame times is mostly that drift, not noise (funnel's
  // c on an H200 varies 19% so, with passes agreeing within 11%). The differences between
  // successive frames cancel a slow drift and keep the jitter: for independent normal noise
  // of deviation s, the median of |t[k+1] - t[k]| is 0.954 s.
  std::vector<double> steps, sorted = t;
  for (size_t k = 1; k < t.size(); ++k) steps.push_back(std::fabs(t[k] - t[k - 1]));
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
  };
  const double typical = median(sorted);
  m.cv = typical > 0 ? median(steps) / 0.954 / typical : 0.0;
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
                  "noisy run: frame times jitter by %.1f%% (from successive differences over the %zu measured '%s' "
                  "frames of one pass), above %.0f%%; measure the noise with --repeat 5, or run on a quieter machine",
                  100.0 * m.cv, m.frames, m.op.c_str(), 100.0 * kNoiseWarningLimit);
  return text;
}

std::string host_load_warning() {
  double load[1] = {0};
  const long cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (getloadavg(load, 1) != 1 || cores <= 0 || load[0] < 0.5 * double(cores)) return "";
  char text[256];
  std::snprintf(text, sizeof text,
                "the host is busy before the run (load average %.2f over the last minute on %ld cores): its timings "
                "will be noisy and may not compare with a run on a quiet host",
                load[0], cores);
  return text;
}

}  // namespace cdb
