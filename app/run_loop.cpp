#include "run_loop.h"
#include "results_readable.h"
#include "exit_codes.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "cdbench/geometry/position_rounding.h"
#include "interrupt.h"
#include "library_errors.h"
#include "noise_check.h"
#include "query_pairs.h"
#include "cdbench/narrow/contacts.h"
#include "cdbench/pipeline/plan_record.h"
#include "cdbench/pipeline/run_summary.h"
#include "report.h"

namespace cdb {
namespace {

// `previous`: the positions of the frame before (the frame's own on the first frame of a
// pass, where swept boxes are discrete too).
void check_frame_pairs(Pipeline& pipeline, const std::vector<PrimPair>& expected, const std::vector<Tri>& faces,
                       const std::vector<vec3f>& previous, const std::vector<vec3f>& vertices,
                       const ContactCheck& contact, FrameStats& s) {
  const std::vector<PrimPair> reported = pipeline.sorted_pairs();
  const PairAccuracy a = pair_accuracy(expected, reported);
  s.check.checked = true;
  s.check.recall = a.recall;
  s.check.precision = a.precision;
  s.check.missed = a.missed;
  s.check.false_positives = a.false_positives;
  s.check.contacts = count_true_contacts(faces, vertices, reported, contact.distance);
  s.check.contact_precision = contact_precision(s.check.contacts, reported.size());
  const std::vector<PrimPair> beyond_discrete = diff_pair_sets(expected, reported, SIZE_MAX).unexpected;
  s.check.discrete_missed_contacts =
      count_interval_contacts(faces, previous, vertices, beyond_discrete, contact.distance, contact.substeps);
}

// Sample mean and relative standard deviation (0 for fewer than two samples).
std::pair<double, double> mean_and_noise(const std::vector<double>& v) {
  double mean = 0;
  for (double x : v) mean += x;
  mean /= double(v.size());
  if (v.size() < 2 || mean <= 0) return {mean, 0.0};
  double ss = 0;
  for (double x : v) ss += (x - mean) * (x - mean);
  return {mean, std::sqrt(ss / double(v.size() - 1)) / mean};
}

// A frame's op where its passes ran different operations: the recorded pass's first, then
// the others', joined by '|'; those that do not fit the results file's text column are
// counted ("|+2").
std::string mixed_op(const std::vector<std::string>& ops) {
  std::string text = ops[0];
  for (size_t i = 1; i < ops.size(); ++i) {
    const std::string rest = i + 1 < ops.size() ? "|+" + std::to_string(ops.size() - i - 1) : "";
    if (text.size() + 1 + ops[i].size() + rest.size() > kTextColumnBytes)
      return text + "|+" + std::to_string(ops.size() - i);
    text += "|" + ops[i];
  }
  return text;
}

// A pass's plan, from its frames' plan steps; none when a frame has none (a pipeline
// without a frame plan).
std::shared_ptr<const RecordedPlan> plan_of_pass(const std::vector<FrameStats>& pass, uint32_t first,
                                                 const std::string& source) {
  auto plan = std::make_shared<RecordedPlan>();
  plan->source = source;
  plan->records_probes = true;
  for (size_t k = 0; k < pass.size(); ++k) {
    if (!pass[k].plan) return nullptr;
    plan->frames.push_back({first + uint32_t(k), *pass[k].plan, 0});
  }
  return plan;
}

// The times of the passes run before the recording one (--repeat), per frame.
struct EarlierPasses {
  std::vector<std::vector<FrameStats>> passes;

  size_t count() const { return passes.size(); }
  // Frame k's times in every pass, pass 0 first and `recording` (the last pass's) last: a
  // /passes row.
  std::vector<FrameTiming> timings(size_t k, const FrameTiming& recording) const {
    std::vector<FrameTiming> t;
    for (const auto& p : passes) t.push_back(p[k].timing);
    t.push_back(recording);
    return t;
  }
  // Relative standard deviation of the passes' mean frame time over the measured frames.
  double noise_of_means(uint32_t warmup) const {
    std::vector<double> means;
    for (const auto& p : passes) {
      double sum = 0;
      size_t k = 0;
      for (size_t f = std::min<size_t>(warmup, p.size() - 1); f < p.size(); ++f, ++k) sum += p[f].timing.total_ms;
      means.push_back(sum / double(k));
    }
    return mean_and_noise(means).second;
  }
  // Frame k of the recording pass becomes the mean over all passes; pair counts must agree.
  // Passes whose plan step differs from the recording pass's are counted (plan_mixed), and
  // their ops join the frame's op.
  void merge_into(size_t k, uint32_t frame, FrameStats& s) const {
    if (passes.empty()) return;
    std::vector<double> totals{s.timing.total_ms};
    std::array<double, kPhaseCount> phase = s.timing.phase_ms;
    std::vector<std::string> ops{s.op};
    for (size_t p = 0; p < passes.size(); ++p) {
      const FrameStats& e = passes[p][k];
      if (e.pairs != s.pairs)
        fail("frame " + std::to_string(frame) + ": pass " + std::to_string(p + 1) + " reported " +
             std::to_string(e.pairs) + " pairs, the last pass " + std::to_string(s.pairs) +
             " (--repeat needs a deterministic pipeline)");
      totals.push_back(e.timing.total_ms);
      for (size_t q = 0; q < kPhaseCount; ++q) phase[q] += e.timing.phase_ms[q];
      if (e.plan == s.plan) continue;
      ++s.plan_mixed;
      if (std::find(ops.begin(), ops.end(), e.op) == ops.end()) ops.push_back(e.op);
    }
    if (ops.size() > 1) s.op = mixed_op(ops);
    const auto [mean, noise] = mean_and_noise(totals);
    s.timing.total_ms = mean;
    s.timing.total_noise = noise;
    s.timing.repeats = uint32_t(totals.size());
    for (size_t q = 0; q < kPhaseCount; ++q) s.timing.phase_ms[q] = phase[q] / double(totals.size());
  }
};

// The least a frame must move through memory: every vertex position and face index read
// once to bound the triangles, every pair written once.
uint64_t frame_bytes_floor(const Topology& t, uint64_t pairs) {
  return 12ull * t.num_vertices + 12ull * t.faces.size() + 8ull * pairs;
}

// One summary line on how the passes' plans were made and whether they agree; none for
// pipelines without a frame plan.
void print_plan_line(const std::vector<FrameStats>& frames, const RunLoopOptions& options, uint32_t first) {
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

// One run_frames call: the passes over the frames, the per-frame --check, the results
// file and the console, as named steps over the state they share.
class FrameLoop {
 public:
  FrameLoop(Pipeline& pipeline, const FrameSource& source, FrameRange range, ResultsFile* out,
            const InterruptScope& interrupts, const RunLoopOptions& options)
      : pipeline_(pipeline),
        source_(source),
        range_(range),
        out_(out),
        interrupts_(interrupts),
        options_(options),
        frames_per_pass_(range.last - range.first),
        progress_(frames_per_pass_ * options.repeat, options.progress),
        f_(range.first) {}

  // Every pass (--repeat), the last one recorded; stops between frames on a signal.
  void run_passes() {
    warm_up();
    // Around the measured passes, not the warm-up, which brings the clocks up first.
    gpu_.before = gpu_reading();
    run_earlier_passes();
    if (interrupts_.signal() && earlier_.count() > 0) {
      keep_finished_passes();
      gpu_.after = gpu_reading();
      return;
    }
    // Each pass starts from a fresh state, so every pass takes the same decisions.
    if (earlier_.count() > 0) pipeline_.set_topology(source_.topology());
    run_recording_pass();
    gpu_.after = gpu_reading();
  }

  // The frame under way (at an error, the one that failed).
  uint32_t frame() const { return f_; }

  // After an error: the file closed as incomplete, saying at which frame and why.
  void abandon(const std::exception& e) {
    progress_.finish();
    if (!out_) return;
    out_->abandon(summary(), pipeline_.memory(),
                  "frame " + std::to_string(f_) + ": " + error_text(e));
    tell_incomplete(*out_);
  }

  // The summary and warnings; then the file finished, or closed as incomplete when a
  // signal stopped the run (its exit code returned).
  int finish(RunResult* result) {
    progress_.finish();
    print_summary(frames_, options_.warmup, pipeline_.memory(), options_.copy_gbps, options_.contact,
                  options_.list_growth);
    print_plan_line(frames_, options_, range_.first);
    if (warmup_frames_)
      std::printf("  warm-up     %llu frames run untimed first (--warmup-ms %g), then the pipeline started afresh\n",
                  static_cast<unsigned long long>(warmup_frames_), options_.warmup_ms);
    if (!options_.accuracy_warning.empty()) print_accuracy_warning(options_.accuracy_warning, frames_, options_.warmup);
    if (const int signal = interrupts_.signal()) return stop_for(signal);
    // After the summary it qualifies; stored so `compare` can flag the run.
    RunFindings findings;
    findings.noise_warning = noise_warning(measure_noise(frames_, options_.warmup));
    if (!findings.noise_warning.empty()) std::printf("  warning     %s\n", findings.noise_warning.c_str());
    // After the frames, so that load which began during the run is seen too.
    const HostLoad after = sample_host_load(options_.load_window_ms);
    findings.host_busy_after = after.busy_share;
    findings.host_warning_after = host_load_warning(after, "after the measured frames");
    if (!findings.host_warning_after.empty()) std::printf("  warning     %s\n", findings.host_warning_after.c_str());
    findings.gpu = gpu_;
    print_gpu_line(gpu_);
    const std::string gpu_notes = gpu_poor_conditions(gpu_.before, gpu_.after);
    if (!gpu_notes.empty()) std::printf("  warning     %s\n", gpu_notes.c_str());
    findings.poor_conditions = poor_conditions(options_.host_before, after, findings.noise_warning, gpu_notes);
    if (!findings.poor_conditions.empty())
      std::printf("  conditions  poor: %s (recorded; compare calls its differences inconclusive)\n",
                  findings.poor_conditions.c_str());
    if (options_.input_hash) findings.input_hash = options_.input_hash();
    if (result) {
      result->summary = summary();
      result->memory = pipeline_.memory();
      result->noise_warning = findings.noise_warning;
      result->input_hash = findings.input_hash;
      result->poor_conditions = findings.poor_conditions;
      result->gpu = gpu_;
    }
    if (out_) finish_file(findings);
    return kExitOk;
  }

 private:
  RunSummary summary() const {
    RunSummary s = summarize_run(frames_, options_.warmup);
    s.warmup_frames = warmup_frames_;
    return s;
  }

  GpuReading gpu_reading() const {
    return options_.probe ? options_.probe->gpu_conditions() : absent_gpu_reading("no device probe");
  }

  FrameStats run_one(uint32_t frame) {
    source_.positions(frame, positions_);
    if (options_.cold) options_.probe->flush_caches();
    FrameStats s = pipeline_.run_frame(positions_);
    s.timing.bytes_floor = frame_bytes_floor(source_.topology(), s.pairs);
    if (query_pairs_.active()) s.query_pairs = query_pairs_.count(pipeline_.sorted_pairs());
    progress_.update(++done_);
    return s;
  }

  // --warmup-ms: frames run and dropped until the time is spent (at least one, the build
  // frame; where frames are kept in memory, to the end of a pass, so none is loaded for the
  // first time between timed frames), each wrap to the first frame and the end from a fresh
  // state, so the measured passes start as the first did but on a warm device and process.
  void warm_up() {
    if (!(options_.warmup_ms > 0.0)) return;
    const auto start = std::chrono::steady_clock::now();
    const auto spent = [&] {
      return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() >=
             options_.warmup_ms;
    };
    bool done = false;
    while (!done && !interrupts_.signal()) {
      for (f_ = range_.first; f_ < range_.last && !interrupts_.signal(); ++f_) {
        source_.positions(f_, positions_);
        pipeline_.run_frame(positions_);
        ++warmup_frames_;
        if (!options_.frames_kept && (done = spent())) break;
      }
      pipeline_.set_topology(source_.topology());
      done = done || spent();
    }
  }

  // --repeat: the passes before the recording one, timed only; fewer once --max-noise is
  // met. A pass a signal cut short is dropped.
  void run_earlier_passes() {
    while (earlier_.count() + 1 < options_.repeat && !interrupts_.signal()) {
      if (earlier_.count() > 0) pipeline_.set_topology(source_.topology());
      earlier_.passes.emplace_back();
      for (f_ = range_.first; f_ < range_.last && !interrupts_.signal(); ++f_)
        earlier_.passes.back().push_back(run_one(f_));
      if (earlier_.passes.back().size() < frames_per_pass_) break;
      finish_earlier_pass();
      if (options_.max_noise_pct > 0 && earlier_.count() >= 2 &&
          earlier_.noise_of_means(options_.warmup) < options_.max_noise_pct / 100.0)
        break;
    }
    if (earlier_.count() > 0 && earlier_.passes.back().size() < frames_per_pass_) earlier_.passes.pop_back();
  }

  // A finished pass before the recording one: its plan into the results file, and under
  // --repeat-plan replay the first pass's plan handed to the pipeline for the passes after.
  void finish_earlier_pass() {
    const uint32_t pass = uint32_t(earlier_.count() - 1);
    const std::vector<FrameStats>& frames = earlier_.passes.back();
    record_plan(pass, frames);
    if (pass > 0 || options_.repeat_plan != RepeatPlan::replay || !options_.plan_source.empty()) return;
    if (auto plan = plan_of_pass(frames, range_.first, "pass 0")) pipeline_.replay_plan(std::move(plan));
  }

  // /plans: the plan steps of `frames`, the first frames of pass `pass`.
  void record_plan(uint32_t pass, const std::vector<FrameStats>& frames) {
    if (!out_) return;
    for (size_t k = 0; k < frames.size(); ++k)
      if (frames[k].plan) out_->append_plan_step(pass, range_.first + uint32_t(k), *frames[k].plan);
  }

  // Stopped before the recording pass: the finished passes are the result, the last of
  // them recorded with the mean of all. --check and --save-pairs need the recording pass's
  // pipeline state, so those frames have neither.
  void keep_finished_passes() {
    const std::vector<FrameStats> last = std::move(earlier_.passes.back());
    earlier_.passes.pop_back();
    kept_passes_ = uint32_t(earlier_.count() + 1);
    for (size_t k = 0; k < last.size(); ++k) {
      f_ = range_.first + uint32_t(k);
      frames_.push_back(last[k]);
      const std::vector<FrameTiming> passes = earlier_.timings(k, last[k].timing);
      earlier_.merge_into(k, f_, frames_.back());
      record(f_, false, passes);
    }
  }

  void run_recording_pass() {
    const uint32_t pass = uint32_t(earlier_.count());
    for (f_ = range_.first; f_ < range_.last && !interrupts_.signal(); ++f_) {
      frames_.push_back(run_one(f_));
      if (out_ && frames_.back().plan) out_->append_plan_step(pass, f_, *frames_.back().plan);
      const std::vector<FrameTiming> passes = earlier_.timings(frames_.size() - 1, frames_.back().timing);
      earlier_.merge_into(frames_.size() - 1, f_, frames_.back());
      if (options_.check_every) check(f_);
      record(f_, options_.save_pairs, passes);
    }
  }

  // --check, after the timed frame. The pass's first frame has no previous one (its swept
  // boxes are its own boxes), so its interval is the frame itself.
  void check(uint32_t frame) {
    if (frame == range_.first) contact_rounding_.restart();
    contact_rounding_.round(positions_, vertices_);
    if (frame == range_.first) previous_ = vertices_;
    if ((frame - range_.first) % options_.check_every == 0)
      check_frame_pairs(pipeline_, options_.oracle(positions_), *options_.faces, previous_, vertices_,
                        options_.contact, frames_.back());
    previous_ = vertices_;
  }

  // The last frame into the results file (its pairs too with `pairs`, and its times in every
  // pass) and onto the console.
  void record(uint32_t frame, bool pairs, const std::vector<FrameTiming>& passes) {
    if (out_) {
      out_->append_frame(frame, frames_.back(), pipeline_.memory());
      out_->append_passes(frame, passes);
      if (pairs) out_->write_pairs(frame, pipeline_.sorted_pairs());
    }
    if (options_.frame_lines) {
      progress_.clear();
      print_frame_line(frame, frames_.back());
    }
  }

  int stop_for(int signal) {
    const std::string why =
        kept_passes_ ? std::string("interrupted by ") + signal_name(signal) + " after " +
                           std::to_string(kept_passes_) + " of " + std::to_string(options_.repeat) +
                           " passes (the finished passes kept)"
                     : std::string("interrupted by ") + signal_name(signal) + " after " +
                           std::to_string(frames_.size()) + " of " + std::to_string(frames_per_pass_) + " frames";
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: %s\n", why.c_str());
    if (out_) {
      out_->abandon(summary(), pipeline_.memory(), why);
      tell_incomplete(*out_);
    }
    return exit_for_signal(signal);
  }

  void finish_file(const RunFindings& findings) {
    try {
      out_->finish(summary(), pipeline_.memory(), findings);
    } catch (const std::exception&) {
      tell_incomplete(*out_);  // e.g. the disk filled while the summary was written
      throw;
    }
    std::printf("results: %s (%llu frames)\n", out_->path().c_str(), static_cast<unsigned long long>(out_->rows()));
  }

  Pipeline& pipeline_;
  const FrameSource& source_;
  const FrameRange range_;
  ResultsFile* const out_;
  const InterruptScope& interrupts_;
  const RunLoopOptions& options_;
  const uint32_t frames_per_pass_;
  Progress progress_;
  uint32_t done_ = 0;
  std::vector<FrameStats> frames_;
  std::vector<vec3d> positions_;
  const QueryPairCounter query_pairs_{source_.topology()};
  // --check's contacts: the frame (and the one before) rebased and rounded as fp64 rounds
  // them, so exact float tests see the scene's geometry whatever the pipeline's precision.
  PositionRounding contact_rounding_{true};
  std::vector<vec3f> vertices_, previous_;
  EarlierPasses earlier_;
  GpuConditions gpu_;  // read just before the measured passes and right after them
  uint64_t warmup_frames_ = 0;  // frames --warmup-ms ran untimed
  uint32_t kept_passes_ = 0;  // --repeat stopped by a signal: the finished passes recorded
  uint32_t f_;                // the frame under way, for the message of an error
};

}  // namespace

const char* repeat_plan_name(RepeatPlan p) { return p == RepeatPlan::free ? "free" : "replay"; }

int run_frames(Pipeline& pipeline, const FrameSource& source, FrameRange range, ResultsFile* out,
               const InterruptScope& interrupts, const RunLoopOptions& options, RunResult* result) {
  if (options.repeat == 0) fail("--repeat must be at least 1");
  if (options.cold && !options.probe) fail("--cold needs the device's cache flush");
  FrameLoop loop(pipeline, source, range, out, interrupts, options);
  try {
    loop.run_passes();
  } catch (const UsageError& e) {
    // An option the frame's data cannot serve (--box-margin past float range): named
    // with the frame, as the results file's reason is.
    loop.abandon(e);
    throw UsageError("frame " + std::to_string(loop.frame()) + ": " + e.what());
  } catch (const std::exception& e) {
    loop.abandon(e);
    throw;
  }
  return loop.finish(result);
}

}  // namespace cdb
