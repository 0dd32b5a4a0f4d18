#pragma once
// The frame loop of `cdbench run`: frames through the pipeline, per-frame lines, progress,
// the results file, and a clean stop on an error or SIGINT/SIGTERM.
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "frame_range.h"
#include "interrupt.h"
#include "noise_check.h"
#include "cdbench/geometry/frame_source.h"
#include "harness/results/results_file.h"
#include "cdbench/narrow/contacts.h"
#include "cdbench/pipeline/device_probe.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/run_summary.h"
#include "progress.h"

namespace cdb {

// --repeat-plan: how the passes of a front pipeline plan their frames. replay: the first
// pass plans (adaptively, or as --front-cycle says) and every later pass replays its
// recorded plan, so each frame's mean is over the same operations; free: every pass plans
// for itself, and frames whose passes ran different operations are marked.
enum class RepeatPlan { replay, free };

const char* repeat_plan_name(RepeatPlan p);

// The run command binds its options --warmup, --save-pairs, --repeat, --repeat-plan,
// --max-noise and --cold straight into this struct (run_command.h); the rest is set per
// pipeline.
struct RunLoopOptions {
  uint32_t warmup = 1;
  // --warmup-ms: the frames run untimed from the first, in order and again from the first
  // after the last, for at least this long before the measured passes, then the pipeline
  // starts afresh (0: none). A first load of each frame between timed frames otherwise
  // slows them on the GPU (docs/usage.md "Warm-up").
  double warmup_ms = 1000.0;
  // The frames are kept in memory after their first load (several pipelines or passes): the
  // warm-up then ends at the end of a pass, so every frame was loaded before the timing.
  bool frames_kept = false;
  bool save_pairs = false;  // each frame's sorted pairs into the results file
  // --repeat: at most this many passes over the frames, each from a fresh pipeline state;
  // the last records, its times the mean over all passes with their noise beside them.
  uint32_t repeat = 1;
  RepeatPlan repeat_plan = RepeatPlan::replay;
  // --front-cycle FILE: the plan every pass replays, as named ("" when none; the pipeline
  // was given it before the run).
  std::string plan_source;
  // --max-noise, in percent: fewer passes once the passes' mean frame times agree within
  // this relative standard deviation (0: always `repeat` passes).
  double max_noise_pct = 0.0;
  // --cold: caches flushed through `probe` before every frame (outside its timing).
  bool cold = false;
  // --load-window-ms: the host's load is sampled over this span before the run and after
  // each pipeline's measured frames (0: not sampled, recorded as absent).
  double load_window_ms = 200.0;

  bool frame_lines = true;  // one line per frame on stdout
  bool list_growth = true;  // the summary names each buffer that grew (--quiet: only their count)
  Progress::Mode progress = Progress::Mode::off;
  // --check: compare every check_every-th frame (0: none) with `oracle`'s pairs for the
  // same positions in double (the scene's geometry, not the pipeline's floats), outside the
  // timed frame.
  uint32_t check_every = 0;
  std::function<std::vector<PrimPair>(const std::vector<vec3d>&)> oracle;
  DeviceProbe* probe = nullptr;
  // The device's measured copy bandwidth, for the bandwidth floor in the summary (0: none).
  double copy_gbps = 0.0;
  // The scene's faces, to count which checked pairs are true contacts (narrow/contacts.h),
  // and what counts as one (--contact-distance, --contact-substeps).
  const std::vector<Tri>* faces = nullptr;
  ContactCheck contact;
  // Set when the configuration can miss pairs (--refit-every): printed after the summary,
  // with the measured recall when frames were checked.
  std::string accuracy_warning;
  // The input's content hash once every frame has run (io/results_file.h RunFindings);
  // unset: none recorded.
  std::function<std::string()> input_hash;
  // The host's load sampled before the run (app/noise_check.h); the loop samples it again
  // after the measured frames, and the two with the noise warning make the run's conditions.
  HostLoad host_before{std::nan(""), 0};
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
