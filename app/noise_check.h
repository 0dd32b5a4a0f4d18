#pragma once
// The noise warning of `cdbench run` (docs/usage.md, "Noise"): printed after the summary,
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

// A warning when at least half the host's CPU time is in use, sampled over 0.2 s before a
// run starts (others' work then shares the cores and the memory bus: two runs of one CPU
// scene on a loaded host measured 99.3 and 7.9 ms per frame); "" otherwise.
std::string host_load_warning();

}  // namespace cdb
