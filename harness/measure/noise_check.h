#pragma once
// The noise warning of `cdbench run` (docs/usage.md "Measurement"): printed after the summary,
// stored in the results file (noise_warning), and flagged by `cdbench compare`.
#include <string>
#include <vector>

#include "cdbench/pipeline/pipeline.h"

namespace cdb {

// A run is noisy above this coefficient of variation (10%): beyond it a 5% change between
// two runs of a few frames cannot be told from noise.
inline constexpr double kNoiseWarningLimit = 0.10;

// The measured frames' noise and what it is: with --repeat, the median over frames of the
// relative standard deviation over the passes (the summary's noise); with one pass, the
// jitter of the measured frames that did the most common operation (so a front update every
// few frames, real work, does not count as noise), from the median difference between
// successive frames relative to their median (so a slow workload drift does not either).
// `frames` under 2 (one pass: under 3): none.
struct NoiseMeasure {
  double cv = 0;
  size_t frames = 0;   // frames it is over
  uint32_t passes = 1;
  std::string op;      // one pass: the operation of the frames it is over
};
NoiseMeasure measure_noise(const std::vector<FrameStats>& frames, uint32_t warmup);

// The warning, naming the number and what to do; "" when the noise is within the limit.
std::string noise_warning(const NoiseMeasure& m);

// The host's load: the share of all its cores' time in use by other processes, sampled over
// window_ms (NaN where /proc/stat cannot be read or window_ms is 0), and its online cores.
// /proc/stat counts in ticks of 10 ms: a window of 200 ms on 2 cores has 40.
struct HostLoad {
  double busy_share = 0;
  long cores = 0;
};
HostLoad sample_host_load(double window_ms);

// A host is busy at this share of its CPU time in use by other work: others' work then
// shares the cores and the memory bus (two runs of one CPU scene on a loaded host measured
// 99.3 and 7.9 ms per frame).
inline constexpr double kBusyHostShare = 0.5;

// A warning when `load` is busy, naming when it was sampled (`when`: "before the run",
// "after the measured frames"); "" otherwise.
std::string host_load_warning(const HostLoad& load, const std::string& when);

// Whether the run's conditions allow its times to be compared: the reasons they do not (a
// busy host before or after the measured frames, a noise warning, and `gpu_notes`, the
// GPU's: cdbench/pipeline/gpu_conditions.h), joined by "; "; "" when they were good.
// Stored in the results file (conditions, conditions_notes).
std::string poor_conditions(const HostLoad& before, const HostLoad& after, const std::string& noise_warning,
                            const std::string& gpu_notes = "");

}  // namespace cdb
