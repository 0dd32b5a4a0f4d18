#pragma once
// The console of `cdbench run`'s frame loop (harness/measure/measuring_loop.h measures):
// per-frame lines, progress, the summary and its warnings, the results file finished, and a
// clean stop on an error or SIGINT/SIGTERM.
#include <string>

#include "frame_range.h"
#include "interrupt.h"
#include "cdbench/geometry/frame_source.h"
#include "harness/measure/measuring_loop.h"
#include "harness/results/results_file.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/run_summary.h"
#include "progress.h"

namespace cdb {

// The console's part of a run; how it measures is `measuring`, which the run command's
// --warmup, --save-pairs, --repeat, --repeat-plan, --max-noise, --cold and --load-window-ms
// bind straight into (run_command.h); the rest is set per pipeline.
struct RunLoopOptions {
  MeasuringOptions measuring;
  bool frame_lines = true;  // one line per frame on stdout
  bool list_growth = true;  // the summary names each buffer that grew (--quiet: only their count)
  Progress::Mode progress = Progress::Mode::off;
  // The device's measured copy bandwidth, for the bandwidth floor in the summary (0: none).
  double copy_gbps = 0.0;
  // Set when the configuration can miss pairs (--refit-every): printed after the summary,
  // with the measured recall when frames were checked.
  std::string accuracy_warning;
};

// What a finished run reports beyond its exit status (run --json).
struct RunResult {
  RunSummary summary;
  MemoryStats memory;
  std::string noise_warning;  // "" when the noise is within kNoiseWarningLimit
  std::string input_hash;
  std::string poor_conditions;  // why the conditions were poor, "" when good
  GpuConditions gpu;  // the GPU's readings around the measured passes
};

// Runs the frames of `range` (repeat passes of them), prints the summary and, given a results file, records every
// frame and marks it complete. On an error the file is closed as incomplete with the
// message and the error is rethrown; on SIGINT/SIGTERM (checked between frames) the same,
// and the return value is 128 + the signal. Returns 0 otherwise.
// `result`, when given, receives the summary of a run that ended without error or signal.
// `interrupts`: the scope the caller installed before it created `out`, so a signal that
// came between then and the first frame is seen too.
int run_frames(Pipeline& pipeline, const FrameSource& source, FrameRange range, ResultsFile* out,
               const InterruptScope& interrupts, const RunLoopOptions& options, RunResult* result = nullptr);

}  // namespace cdb
