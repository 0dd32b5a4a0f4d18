#include "harness/measure/noise_check.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdio>
#include <map>
#include <thread>
#include <utility>

#include <sys/times.h>
#include <unistd.h>

#include "cdbench/pipeline/run_summary.h"

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
    if (frames[f].op == m.op) t.push_back(frames[f].timing.total_ms);
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

namespace {

// Busy and total jiffies of all cores, from /proc/stat's first line; false where unreadable.
bool cpu_jiffies(unsigned long long& busy, unsigned long long& total) {
  std::FILE* f = std::fopen("/proc/stat", "r");
  if (!f) return false;
  unsigned long long v[8] = {};
  const int n = std::fscanf(f, "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &v[0], &v[1], &v[2], &v[3], &v[4],
                            &v[5], &v[6], &v[7]);
  std::fclose(f);
  if (n < 5) return false;
  total = 0;
  for (unsigned long long x : v) total += x;
  busy = total - v[3] - v[4];  // idle and iowait
  return true;
}

}  // namespace

HostLoad sample_host_load(double window_ms) {
  // Sampled now rather than the load average, which still holds a build that just ended.
  HostLoad load;
  load.busy_share = std::nan("");
  load.cores = sysconf(_SC_NPROCESSORS_ONLN);
  if (!(window_ms > 0)) return load;
  // The process's own time is taken out: after the frames its OpenMP threads may still spin
  // at their barrier, which is this run's doing, not other work's. times() counts in clock
  // ticks, the unit of /proc/stat.
  unsigned long long busy0 = 0, total0 = 0, busy1 = 0, total1 = 0;
  tms own0{}, own1{};
  if (!cpu_jiffies(busy0, total0) || times(&own0) == clock_t(-1)) return load;
  std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(window_ms));
  if (!cpu_jiffies(busy1, total1) || total1 <= total0 || times(&own1) == clock_t(-1)) return load;
  const double own = double((own1.tms_utime + own1.tms_stime) - (own0.tms_utime + own0.tms_stime));
  load.busy_share = std::max(0.0, double(busy1 - busy0) - own) / double(total1 - total0);
  return load;
}

std::string host_load_warning(const HostLoad& load, const std::string& when) {
  if (load.cores <= 0 || !(load.busy_share >= kBusyHostShare)) return "";
  char text[256];
  std::snprintf(text, sizeof text,
                "the host is busy %s (%.0f%% of its %ld cores in use by other work): its timings will be "
                "noisy and may not compare with a run on a quiet host",
                when.c_str(), 100.0 * load.busy_share, load.cores);
  return text;
}

std::string poor_conditions(const HostLoad& before, const HostLoad& after, const std::string& noise_warning,
                            const std::string& gpu_notes) {
  std::string notes;
  const auto add = [&notes](const std::string& why) { notes += (notes.empty() ? "" : "; ") + why; };
  char text[128];
  for (const auto& [load, when] : {std::pair{&before, "before the run"}, std::pair{&after, "after the measured frames"}})
    if (load->busy_share >= kBusyHostShare) {
      std::snprintf(text, sizeof text, "host busy %s (%.0f%%)", when, 100.0 * load->busy_share);
      add(text);
    }
  if (!noise_warning.empty()) add("noise warning");
  if (!gpu_notes.empty()) add(gpu_notes);
  return notes;
}

}  // namespace cdb
