#include "run_loop.h"
#include "results_readable.h"
#include "exit_codes.h"

#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/pipeline/run_summary.h"
#include "interrupt.h"
#include "library_errors.h"
#include "report.h"

namespace cdb {
namespace {

// One summary line on how the passes' plans were made and whether they agree; none for
// pipelines without a frame plan.
void print_plan_line(const std::vector<FrameStats>& frames, const MeasuringOptions& options, uint32_t first) {
  if (frames.empty() || !frames.front().plan) return;
  const uint32_t passes = frames.back().timing.repeats;
  if (!options.plan_source.empty()) {
    std::printf("  plan        %s replayed %s (--front-cycle)\n", passes > 1 ? "every pass" : "the pass",
                options.plan_source.c_str());
    return;
  }
  if (passes < 2) return;
  if (options.repeat_plan == RepeatPlan::replay) {
    const std::string later = passes == 2 ? "pass 1" : "passes 1 to " + std::to_string(passes - 1);
    std::printf("  plan        %s replayed pass 0's plan (--repeat-plan replay): each frame's mean is over the same "
                "operations\n",
                later.c_str());
    return;
  }
  std::vector<uint32_t> mixed;
  for (size_t k = 0; k < frames.size(); ++k)
    if (frames[k].plan_mixed) mixed.push_back(first + uint32_t(k));
  if (mixed.empty())
    std::printf("  plan        each pass planned its own (--repeat-plan free); all %u ran the same operations\n",
                passes);
  else
    std::printf("  plan        each pass planned its own (--repeat-plan free): %zu of %zu frames ran different "
                "operations in different passes (%s), their means mix them; op shows them joined by |\n",
                mixed.size(), frames.size(), frame_list_text(mixed).c_str());
}

// The GPU's readings around the measured passes, where NVML gave them.
void print_gpu_line(const GpuConditions& gpu) {
  if (!gpu.before.read() || !gpu.after.read()) return;
  const GpuReading &b = gpu.before, &a = gpu.after;
  std::printf("  gpu         SM %.0f to %.0f MHz, memory %.0f MHz, %.0f to %.0f C, %.0f to %.0f W; clock limits after: "
              "%s (NVML, before and after the measured passes)\n",
              b.sm_clock_mhz, a.sm_clock_mhz, a.mem_clock_mhz, b.temperature_c, a.temperature_c, b.power_w,
              a.power_w, throttle_reasons_text(a.throttle_reasons).c_str());
}

void print_accuracy_warning(const std::string& why, const std::vector<FrameStats>& frames, uint32_t warmup) {
  const RunSummary r = summarize_run(frames, warmup);
  if (r.checked_frames)
    std::printf("  warning     %s; measured recall min %.6f over %zu checked frames (%llu missed)\n", why.c_str(),
                r.recall_min, r.checked_frames, static_cast<unsigned long long>(r.missed));
  else
    std::printf("  warning     %s; recall not measured (use --check)\n", why.c_str());
}

// Where an abandoned run's results are, and that the file it was to replace is as it was.
// A file a failed write left unreadable is removed rather than named as results.
void tell_incomplete(const ResultsFile& out) {
  const std::optional<bool> readable = out.intact() ? true : results_readable(out.path());
  if (readable == false) {
    std::error_code ec;
    std::filesystem::remove(out.path(), ec);
    if (ec)
      std::fprintf(stderr, "cdbench: %s is unreadable after the failed write, and removing it failed: %s\n",
                   out.path().c_str(), ec.message().c_str());
    else
      std::fprintf(stderr, "cdbench: %s removed: the failed write left it unreadable (no results of this run kept)\n",
                   out.path().c_str());
  } else {
    std::fprintf(stderr, "cdbench: results (incomplete%s): %s\n",
                 out.intact()  ? ""
                 : readable    ? ", only what was flushed before the failed write"
                               : ", only what was flushed before the failed write; it may not be readable",
                 out.path().c_str());
  }
  if (out.path() != out.target())
    std::fprintf(stderr, "cdbench: %s left as it was (not replaced)\n", out.target().c_str());
}

// One run_frames call on the console: the measuring loop's progress and frame lines as it
// goes, then the summary, its warnings and the results file finished or abandoned.
class ConsoleRun : public MeasuringEvents {
 public:
  ConsoleRun(MeasuringLoop& loop, Pipeline& pipeline, ResultsFile* out, const InterruptScope& interrupts,
             const RunLoopOptions& options)
      : loop_(loop),
        pipeline_(pipeline),
        out_(out),
        interrupts_(interrupts),
        options_(options),
        progress_(loop.frames_per_pass() * options.measuring.repeat, options.progress) {}

  bool stop_requested() const override { return interrupts_.signal() != 0; }
  void on_frame(uint32_t, uint32_t done) override { progress_.update(done); }
  void on_frame_recorded(uint32_t frame, const FrameStats& stats) override {
    if (!options_.frame_lines) return;
    progress_.clear();
    print_frame_line(frame, stats);
  }

  // After an error: the file closed as incomplete, saying at which frame and why.
  void abandon(const std::exception& e) {
    progress_.finish();
    if (!out_) return;
    out_->abandon(loop_.summary(), pipeline_.memory(), "frame " + std::to_string(loop_.frame()) + ": " + error_text(e));
    tell_incomplete(*out_);
  }

  // The summary and warnings; then the file finished, or closed as incomplete when a
  // signal stopped the run (its exit code returned).
  int finish(RunResult* result) {
    const MeasuringOptions& m = options_.measuring;
    progress_.finish();
    print_summary(loop_.frames(), m.warmup, pipeline_.memory(), options_.copy_gbps, m.contact, options_.list_growth);
    print_plan_line(loop_.frames(), m, loop_.first());
    if (loop_.warmup_frames())
      std::printf("  warm-up     %llu frames run untimed first (--warmup-ms %g), then the pipeline started afresh\n",
                  static_cast<unsigned long long>(loop_.warmup_frames()), m.warmup_ms);
    if (!options_.accuracy_warning.empty()) print_accuracy_warning(options_.accuracy_warning, loop_.frames(), m.warmup);
    if (const int signal = interrupts_.signal()) return stop_for(signal);
    // After the summary they qualify; stored so `compare` can flag the run.
    const RunFindings findings = loop_.findings();
    if (!findings.noise_warning.empty()) std::printf("  warning     %s\n", findings.noise_warning.c_str());
    if (!findings.host_warning_after.empty()) std::printf("  warning     %s\n", findings.host_warning_after.c_str());
    print_gpu_line(findings.gpu);
    const std::string gpu_notes = gpu_poor_conditions(findings.gpu.before, findings.gpu.after);
    if (!gpu_notes.empty()) std::printf("  warning     %s\n", gpu_notes.c_str());
    if (!findings.poor_conditions.empty())
      std::printf("  conditions  poor: %s (recorded; compare calls its differences inconclusive)\n",
                  findings.poor_conditions.c_str());
    if (result) {
      result->summary = loop_.summary();
      result->memory = pipeline_.memory();
      result->noise_warning = findings.noise_warning;
      result->input_hash = findings.input_hash;
      result->poor_conditions = findings.poor_conditions;
      result->gpu = findings.gpu;
    }
    if (out_) finish_file(findings);
    return kExitOk;
  }

 private:
  int stop_for(int signal) {
    const uint32_t kept = loop_.kept_passes();
    const std::string why =
        kept ? std::string("interrupted by ") + signal_name(signal) + " after " + std::to_string(kept) + " of " +
                   std::to_string(options_.measuring.repeat) + " passes (the finished passes kept)"
             : std::string("interrupted by ") + signal_name(signal) + " after " +
                   std::to_string(loop_.frames().size()) + " of " + std::to_string(loop_.frames_per_pass()) +
                   " frames";
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: %s\n", why.c_str());
    if (out_) {
      out_->abandon(loop_.summary(), pipeline_.memory(), why);
      tell_incomplete(*out_);
    }
    return exit_for_signal(signal);
  }

  void finish_file(const RunFindings& findings) {
    try {
      out_->finish(loop_.summary(), pipeline_.memory(), findings);
    } catch (const std::exception&) {
      tell_incomplete(*out_);  // e.g. the disk filled while the summary was written
      throw;
    }
    std::printf("results: %s (%llu frames)\n", out_->path().c_str(), static_cast<unsigned long long>(out_->rows()));
  }

  const MeasuringLoop& loop_;
  Pipeline& pipeline_;
  ResultsFile* const out_;
  const InterruptScope& interrupts_;
  const RunLoopOptions& options_;
  Progress progress_;
};

}  // namespace

int run_frames(Pipeline& pipeline, const FrameSource& source, FrameRange range, ResultsFile* out,
               const InterruptScope& interrupts, const RunLoopOptions& options, RunResult* result) {
  MeasuringLoop loop(pipeline, source, range.first, range.last, out, options.measuring);
  ConsoleRun console(loop, pipeline, out, interrupts, options);
  try {
    loop.run(console);
  } catch (const UsageError& e) {
    // An option the frame's data cannot serve (--box-margin past float range): named
    // with the frame, as the results file's reason is.
    console.abandon(e);
    throw UsageError("frame " + std::to_string(loop.frame()) + ": " + e.what());
  } catch (const std::exception& e) {
    console.abandon(e);
    throw;
  }
  return console.finish(result);
}

}  // namespace cdb
