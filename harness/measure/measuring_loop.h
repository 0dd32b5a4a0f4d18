#pragma once
// The measuring loop: frames through a pipeline with a warm-up, passes over the frames from
// a fresh state each (--repeat), the first pass's plan replayed by the later ones, the noise
// over the passes, a cache flush before every frame (--cold), the per-frame --check, and
// every frame into the results file. It prints nothing: what a caller shows (progress,
// per-frame lines, the summary) it learns through MeasuringEvents and the loop's accessors.
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "cdbench/geometry/frame_source.h"
#include "cdbench/geometry/position_rounding.h"
#include "cdbench/narrow/contacts.h"
#include "cdbench/pipeline/device_probe.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/run_summary.h"
#include "harness/measure/noise_check.h"
#include "harness/measure/query_pairs.h"
#include "harness/results/results_file.h"

namespace cdb {

// --repeat-plan: how the passes of a front pipeline plan their frames. replay: the first
// pass plans (adaptively, or as --front-cycle says) and every later pass replays its
// recorded plan, so each frame's mean is over the same operations; free: every pass plans
// for itself, and frames whose passes ran different operations are marked.
enum class RepeatPlan { replay, free };

const char* repeat_plan_name(RepeatPlan p);

// How the loop measures. The run command binds --warmup, --warmup-ms, --save-pairs,
// --repeat, --repeat-plan, --max-noise, --cold and --load-window-ms straight into it; the
// rest is set per pipeline.
struct MeasuringOptions {
  uint32_t warmup = 1;
  // --warmup-ms: the frames run untimed from the first, in order and again from the first
  // after the last, for at least this long before the measured passes, then the pipeline
  // starts afresh (0: none). A first load of each frame between timed frames otherwise
  // slows them on the GPU (docs/design.md "Measurement method").
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
  // --check: compare every check_every-th frame (0: none) with `oracle`'s pairs for the
  // same positions in double (the scene's geometry, not the pipeline's floats), outside the
  // timed frame.
  uint32_t check_every = 0;
  std::function<std::vector<PrimPair>(const std::vector<vec3d>&)> oracle;
  DeviceProbe* probe = nullptr;
  // The scene's faces, to count which checked pairs are true contacts (narrow/contacts.h),
  // and what counts as one (--contact-distance, --contact-substeps).
  const std::vector<Tri>* faces = nullptr;
  ContactCheck contact;
  // The input's content hash once every frame has run (harness/results/results_file.h
  // RunFindings); unset: none recorded.
  std::function<std::string()> input_hash;
  // The host's load sampled before the run; the loop samples it again after the measured
  // frames, and the two with the noise warning make the run's conditions.
  HostLoad host_before{std::nan(""), 0};
};

// What the loop tells its caller as it goes, and asks it between frames. Every member has a
// default that does nothing, so a caller overrides only what it shows.
class MeasuringEvents {
 public:
  virtual ~MeasuringEvents() = default;
  // Asked between frames (and within the warm-up): true stops the loop there, keeping what
  // is done (a signal came).
  virtual bool stop_requested() const { return false; }
  // A frame of the warm-up ran (untimed, dropped).
  virtual void on_warmup_frame(uint32_t /*frame*/) {}
  // Pass `pass` (0 first; the recording pass last) starts.
  virtual void on_pass_begin(uint32_t /*pass*/) {}
  // A timed frame of any pass ran; `done`: the timed frames so far over all passes.
  virtual void on_frame(uint32_t /*frame*/, uint32_t /*done*/) {}
  // A frame's result is final (the mean over the passes) and in the results file.
  virtual void on_frame_recorded(uint32_t /*frame*/, const FrameStats& /*stats*/) {}
};

// One measurement of `pipeline` over the frames [first, last) of `source`, recorded into
// `out` when given (frames, their passes, plans and pairs; finishing or abandoning the file
// is the caller's, with the loop's summary).
class MeasuringLoop {
 public:
  // Throws when the options cannot be served (repeat 0, --cold without a probe).
  MeasuringLoop(Pipeline& pipeline, const FrameSource& source, uint32_t first, uint32_t last, ResultsFile* out,
                const MeasuringOptions& options);

  // The warm-up and every pass, the last one recorded; stops between frames when
  // events.stop_requested(). Errors propagate with frame() the one that failed.
  void run(MeasuringEvents& events);

  // The frame under way (after an error, the one that failed).
  uint32_t frame() const { return f_; }
  uint32_t first() const { return first_; }
  uint32_t frames_per_pass() const { return frames_per_pass_; }
  // The recorded frames, each the mean over its passes.
  const std::vector<FrameStats>& frames() const { return frames_; }
  // The summary of the recorded frames, with the warm-up frames counted.
  RunSummary summary() const;
  uint64_t warmup_frames() const { return warmup_frames_; }
  // Stopped before the recording pass: the passes finished and kept (0 otherwise).
  uint32_t kept_passes() const { return kept_passes_; }
  // The GPU's readings just before the measured passes and right after them.
  const GpuConditions& gpu() const { return gpu_; }
  // The run's noise, the host's load sampled now (after the measured frames, so load that
  // began during the run is seen too), the GPU's conditions and the input's hash.
  RunFindings findings() const;

 private:
  GpuReading gpu_reading() const;
  FrameStats run_one(uint32_t frame, MeasuringEvents& events);
  void warm_up(MeasuringEvents& events);
  void run_earlier_passes(MeasuringEvents& events);
  void finish_earlier_pass();
  void record_plan(uint32_t pass, const std::vector<FrameStats>& frames);
  void keep_finished_passes(MeasuringEvents& events);
  void run_recording_pass(MeasuringEvents& events);
  void check(uint32_t frame);
  void record(uint32_t frame, bool pairs, const std::vector<FrameTiming>& passes, MeasuringEvents& events);

  // The times of the passes run before the recording one, per frame.
  struct EarlierPasses {
    std::vector<std::vector<FrameStats>> passes;
    size_t count() const { return passes.size(); }
    std::vector<FrameTiming> timings(size_t k, const FrameTiming& recording) const;
    double noise_of_means(uint32_t warmup) const;
    void merge_into(size_t k, uint32_t frame, FrameStats& s) const;
  };

  Pipeline& pipeline_;
  const FrameSource& source_;
  const uint32_t first_, last_;
  ResultsFile* const out_;
  const MeasuringOptions& options_;
  const uint32_t frames_per_pass_;
  uint32_t done_ = 0;
  std::vector<FrameStats> frames_;
  std::vector<vec3d> positions_;
  const QueryPairCounter query_pairs_;
  // --check's contacts: the frame (and the one before) rebased and rounded as fp64 rounds
  // them, so exact float tests see the scene's geometry whatever the pipeline's precision.
  PositionRounding contact_rounding_{true};
  std::vector<vec3f> vertices_, previous_;
  EarlierPasses earlier_;
  GpuConditions gpu_;
  uint64_t warmup_frames_ = 0;  // frames --warmup-ms ran untimed
  uint32_t kept_passes_ = 0;    // --repeat stopped early: the finished passes recorded
  uint32_t f_;                  // the frame under way, for the message of an error
};

}  // namespace cdb
