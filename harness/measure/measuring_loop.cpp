#include "harness/measure/measuring_loop.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "cdbench/pipeline/plan_record.h"

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

// The least a frame must move through memory: every vertex position and face index read
// once to bound the triangles, every pair written once.
uint64_t frame_bytes_floor(const Topology& t, uint64_t pairs) {
  return 12ull * t.num_vertices + 12ull * t.faces.size() + 8ull * pairs;
}

}  // namespace

const char* repeat_plan_name(RepeatPlan p) { return p == RepeatPlan::free ? "free" : "replay"; }

// Frame k's times in every pass, pass 0 first and `recording` (the last pass's) last: a
// /passes row.
std::vector<FrameTiming> MeasuringLoop::EarlierPasses::timings(size_t k, const FrameTiming& recording) const {
  std::vector<FrameTiming> t;
  for (const auto& p : passes) t.push_back(p[k].timing);
  t.push_back(recording);
  return t;
}

// Relative standard deviation of the passes' mean frame time over the measured frames.
double MeasuringLoop::EarlierPasses::noise_of_means(uint32_t warmup) const {
  std::vector<double> means;
  for (const auto& p : passes) {
    double sum = 0;
    size_t k = 0;
    for (size_t f = std::min<size_t>(warmup, p.size() - 1); f < p.size(); ++f, ++k) sum += p[f].timing.total_ms;
    means.push_back(sum / double(k));
  }
  return mean_and_noise(means).second;
}

// Frame k of the recording pass becomes the mean over all passes (its allocations the most
// of any pass); pair counts must agree.
// Passes whose plan step differs from the recording pass's are counted (plan_mixed), and
// their ops join the frame's op.
void MeasuringLoop::EarlierPasses::merge_into(size_t k, uint32_t frame, FrameStats& s) const {
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
    // A pass's first allocations (the first pass's) are what a frame may hide.
    s.timing.allocations = std::max(s.timing.allocations, e.timing.allocations);
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

MeasuringLoop::MeasuringLoop(Pipeline& pipeline, const FrameSource& source, uint32_t first, uint32_t last,
                             ResultsFile* out, const MeasuringOptions& options)
    : pipeline_(pipeline),
      source_(source),
      first_(first),
      last_(last),
      out_(out),
      options_(options),
      frames_per_pass_(last - first),
      query_pairs_(source.topology()),
      f_(first) {
  if (options.repeat == 0) fail("--repeat must be at least 1");
  if (options.cold && !options.probe) fail("--cold needs the device's cache flush");
}

void MeasuringLoop::run(MeasuringEvents& events) {
  warm_up(events);
  // Around the measured passes, not the warm-up, which brings the clocks up first.
  gpu_.before = gpu_reading();
  run_earlier_passes(events);
  if (events.stop_requested() && earlier_.count() > 0) {
    keep_finished_passes(events);
    gpu_.after = gpu_reading();
    return;
  }
  // Each pass starts from a fresh state, so every pass takes the same decisions.
  if (earlier_.count() > 0) pipeline_.set_topology(source_.topology());
  run_recording_pass(events);
  gpu_.after = gpu_reading();
}

RunSummary MeasuringLoop::summary() const {
  RunSummary s = summarize_run(frames_, options_.warmup);
  s.warmup_frames = warmup_frames_;
  return s;
}

RunFindings MeasuringLoop::findings() const {
  RunFindings findings;
  findings.noise_warning = noise_warning(measure_noise(frames_, options_.warmup));
  const HostLoad after = sample_host_load(options_.load_window_ms);
  findings.host_busy_after = after.busy_share;
  findings.host_warning_after = host_load_warning(after, "after the measured frames");
  findings.gpu = gpu_;
  findings.poor_conditions = poor_conditions(options_.host_before, after, findings.noise_warning,
                                             gpu_poor_conditions(gpu_.before, gpu_.after));
  if (options_.input_hash) findings.input_hash = options_.input_hash();
  return findings;
}

GpuReading MeasuringLoop::gpu_reading() const {
  return options_.probe ? options_.probe->gpu_conditions() : absent_gpu_reading("no device probe");
}

FrameStats MeasuringLoop::run_one(uint32_t frame, MeasuringEvents& events) {
  source_.positions(frame, positions_);
  if (options_.cold) options_.probe->flush_caches();
  FrameStats s = pipeline_.run_frame(positions_);
  s.timing.bytes_floor = frame_bytes_floor(source_.topology(), s.pairs);
  if (query_pairs_.active()) s.query_pairs = query_pairs_.count(pipeline_.sorted_pairs());
  events.on_frame(frame, ++done_);
  return s;
}

// --warmup-ms: frames run and dropped until the time is spent (at least one, the build
// frame; where frames are kept in memory, to the end of a pass, so none is loaded for the
// first time between timed frames), each wrap to the first frame and the end from a fresh
// state, so the measured passes start as the first did but on a warm device and process.
void MeasuringLoop::warm_up(MeasuringEvents& events) {
  if (!(options_.warmup_ms > 0.0)) return;
  const auto start = std::chrono::steady_clock::now();
  const auto spent = [&] {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() >=
           options_.warmup_ms;
  };
  bool done = false;
  while (!done && !events.stop_requested()) {
    for (f_ = first_; f_ < last_ && !events.stop_requested(); ++f_) {
      source_.positions(f_, positions_);
      pipeline_.run_frame(positions_);
      ++warmup_frames_;
      events.on_warmup_frame(f_);
      if (!options_.frames_kept && (done = spent())) break;
    }
    pipeline_.set_topology(source_.topology());
    done = done || spent();
  }
}

// --repeat: the passes before the recording one, timed only; fewer once --max-noise is
// met. A pass cut short by a stop is dropped.
void MeasuringLoop::run_earlier_passes(MeasuringEvents& events) {
  while (earlier_.count() + 1 < options_.repeat && !events.stop_requested()) {
    if (earlier_.count() > 0) pipeline_.set_topology(source_.topology());
    events.on_pass_begin(uint32_t(earlier_.count()));
    earlier_.passes.emplace_back();
    for (f_ = first_; f_ < last_ && !events.stop_requested(); ++f_)
      earlier_.passes.back().push_back(run_one(f_, events));
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
void MeasuringLoop::finish_earlier_pass() {
  const uint32_t pass = uint32_t(earlier_.count() - 1);
  const std::vector<FrameStats>& frames = earlier_.passes.back();
  record_plan(pass, frames);
  if (pass > 0 || options_.repeat_plan != RepeatPlan::replay || !options_.plan_source.empty()) return;
  if (auto plan = plan_of_pass(frames, first_, "pass 0")) pipeline_.replay_plan(std::move(plan));
}

// /plans: the plan steps of `frames`, the first frames of pass `pass`.
void MeasuringLoop::record_plan(uint32_t pass, const std::vector<FrameStats>& frames) {
  if (!out_) return;
  for (size_t k = 0; k < frames.size(); ++k)
    if (frames[k].plan) out_->append_plan_step(pass, first_ + uint32_t(k), *frames[k].plan);
}

// Stopped before the recording pass: the finished passes are the result, the last of
// them recorded with the mean of all. --check and --save-pairs need the recording pass's
// pipeline state, so those frames have neither.
void MeasuringLoop::keep_finished_passes(MeasuringEvents& events) {
  const std::vector<FrameStats> last = std::move(earlier_.passes.back());
  earlier_.passes.pop_back();
  kept_passes_ = uint32_t(earlier_.count() + 1);
  for (size_t k = 0; k < last.size(); ++k) {
    f_ = first_ + uint32_t(k);
    frames_.push_back(last[k]);
    const std::vector<FrameTiming> passes = earlier_.timings(k, last[k].timing);
    earlier_.merge_into(k, f_, frames_.back());
    record(f_, false, passes, events);
  }
}

void MeasuringLoop::run_recording_pass(MeasuringEvents& events) {
  const uint32_t pass = uint32_t(earlier_.count());
  events.on_pass_begin(pass);
  for (f_ = first_; f_ < last_ && !events.stop_requested(); ++f_) {
    frames_.push_back(run_one(f_, events));
    if (out_ && frames_.back().plan) out_->append_plan_step(pass, f_, *frames_.back().plan);
    const std::vector<FrameTiming> passes = earlier_.timings(frames_.size() - 1, frames_.back().timing);
    earlier_.merge_into(frames_.size() - 1, f_, frames_.back());
    if (options_.check_every) check(f_);
    record(f_, options_.save_pairs, passes, events);
  }
}

// --check, after the timed frame. The pass's first frame has no previous one (its swept
// boxes are its own boxes), so its interval is the frame itself.
void MeasuringLoop::check(uint32_t frame) {
  if (frame == first_) contact_rounding_.restart();
  contact_rounding_.round(positions_, vertices_);
  if (frame == first_) previous_ = vertices_;
  if ((frame - first_) % options_.check_every == 0)
    check_frame_pairs(pipeline_, options_.oracle(positions_), *options_.faces, previous_, vertices_,
                      options_.contact, frames_.back());
  previous_ = vertices_;
}

// The last frame into the results file (its pairs too with `pairs`, and its times in every
// pass), then told to the caller.
void MeasuringLoop::record(uint32_t frame, bool pairs, const std::vector<FrameTiming>& passes,
                           MeasuringEvents& events) {
  if (out_) {
    out_->append_frame(frame, frames_.back(), pipeline_.memory());
    out_->append_passes(frame, passes);
    if (pairs) out_->write_pairs(frame, pipeline_.sorted_pairs());
  }
  events.on_frame_recorded(frame, frames_.back());
}

}  // namespace cdb
