#pragma once
// The noise warning of `cdbench run` (docs/usage.md, "Noise"): printed after the summary,
// stored in the results file (noise_warning), and flagged by `cdbench compare`.
#include <string>
#include <vector>

#include "pipeline/pipeline.h"

namespace cdb {

// A run is noisy above this coefficient of variation (10%): beyond it a 5% change between
// two runs of a few frames cannot be told from noise.
inline constexpr double kNoiseWarningLimit = 0.10;

// The measured frames' noise and what it is: with --repeat, the median over frames of the
// relative standard deviation over the passes (the summary's noise); with one pass, the
// coefficient of variation of the frame times over the measured frames that did the most
// common operation (so a front update every few frames, real work, does not count as noise;
// workload drift still does, the warning says so). `frames` under 2: none.
struct NoiseMeasure {
  double cv = 0;
  size_t frames = 0;   // frames it is over
  uint32_t passes = 1;
  std::string op;      // one pass: the operation of the frames it is over
};
NoiseMeasure measure_noise(const std::vector<FrameStats>& frames, uint32_t warmup);

// The warning, naming the number and what to do; "" when the noise is within the limit.
std::string noise_warning(const NoiseMeasure& m);

}  // namespace cdb
