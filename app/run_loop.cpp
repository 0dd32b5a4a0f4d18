#include "run_loop.h"
#include "exit_codes.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/pair_set.h"
#include "geometry/position_rounding.h"
#include "interrupt.h"
#include "noise_check.h"
#include "narrow/contacts.h"
#include "pipeline/run_summary.h"
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
  s.checked = true;
  s.recall = a.recall;
  s.precision = a.precision;
  s.missed = a.missed;
  s.false_positives = a.false_positives;
  s.contacts = count_true_contacts(faces, vertices, reported, contact.distance);
  s.contact_precision = contact_precision(s.contacts, reported.size());
  const std::vector<PrimPair> beyond_discrete = diff_pair_sets(expected, reported, SIZE_MAX).unexpected;
  s.discrete_missed_contacts =
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

// The times of the passes run before the recording one (--repeat), per frame.
struct EarlierPasses {
  std::vector<std::vector<FrameStats>> passes;

  size_t count() const { return passes.size(); }
  // Relative standard deviation of the passes' mean frame time over the measured frames.
  double noise_of_means(uint32_t warmup) const {
    std::vector<double> means;
    for (const auto& p : passes) {
      double sum = 0;
      size_t k = 0;
      for (size_t f = std::min<size_t>(warmup, p.size() - 1); f < p.size(); ++f, ++k) sum += p[f].total_ms;
      means.push_back(sum / double(k));
    }
    return mean_and_noise(means).second;
  }
  // Frame k of the recording pass becomes the mean over all passes; pair counts must agree.
  void merge_into(size_t k, uint32_t frame, FrameStats& s) const {
    if (passes.empty()) return;
    std::vector<double> totals{s.total_ms};
    std::array<double, kPhaseCount> phase = s.phase_ms;
    for (size_t p = 0; p < passes.size(); ++p) {
      const FrameStats& e = passes[p][k];
      if (e.pairs != s.pairs)
        fail("frame " + std::to_string(frame) + ": pass " + std::to_string(p + 1) + " reported " +
             std::to_string(e.pairs) + " pairs, the last pass " + std::to_string(s.pairs) +
             " (--repeat needs a deterministic pipeline)");
      totals.push_back(e.total_ms);
      for (size_t q = 0; q < kPhaseCount; ++q) phase[q] += e.phase_ms[q];
    }
    const auto [mean, noise] = mean_and_noise(totals);
    s.total_ms = mean;
    s.total_noise = noise;
    s.repeats = uint32_t(totals.size());
    for (size_t q = 0; q < kPhaseCount; ++q) s.phase_ms[q] = phase[q] / double(totals.size());
  }
};

// The least a frame must move through memory: every vertex position and face index read
// once to bound the triangles, every pair written once.
uint64_t frame_bytes_floor(const Topology& t, uint64_t pairs) {
  return 12ull * t.num_vertices + 12ull * t.faces.size() + 8ull * pairs;
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
void tell_incomplete(const ResultsFile& out) {
  std::fprintf(stderr, "cdbench: results (incomplete%s): %s\n",
               out.intact() ? "" : ", only what was flushed before the failed write", out.path().c_str());
  if (out.path() != out.target())
    std::fprintf(stderr, "cdbench: %s left as it was (not replaced)\n", out.target().c_str());
}

}  // namespace

int run_frames(Pipeline& pipeline, const FrameSource& source, FrameRange range, ResultsFile* out,
               const InterruptScope& interrupts, const RunLoopOptions& options, RunResult* result) {
  if (options.repeat == 0) fail("--repeat must be at least 1");
  if (options.cold && !options.probe) fail("--cold needs the device's cache flush");
  const uint32_t frames_per_pass = range.last - range.first;
  Progress progress(frames_per_pass * options.repeat, options.progress);
  uint32_t done = 0;
  std::vector<FrameStats> frames;
  std::vector<vec3d> positions;
  // --check's contacts: the frame (and the one before) rebased and rounded as fp64 rounds
  // them, so exact float tests see the scene's geometry whatever the pipeline's precision.
  PositionRounding contact_rounding(true);
  std::vector<vec3f> vertices, previous;
  EarlierPasses earlier;
  uint32_t kept_passes = 0;  // --repeat stopped by a signal: the finished passes recorded
  uint32_t f = range.first;
  const auto run_one = [&](uint32_t frame) {
    source.positions(frame, positions);
    if (options.cold) options.probe->flush_caches();
    FrameStats s = pipeline.run_frame(positions);
    s.bytes_floor = frame_bytes_floor(source.topology(), s.pairs);
    progress.update(++done);
    return s;
  };
  try {
    // --repeat: passes before the recording one, timed only; each starts from a fresh
    // state, so every pass takes the same decisions on the same frames.
    while (earlier.count() + 1 < options.repeat && !interrupts.signal()) {
      if (earlier.count() > 0) pipeline.set_topology(source.topology());
      earlier.passes.emplace_back();
      for (f = range.first; f < range.last && !interrupts.signal(); ++f)
        earlier.passes.back().push_back(run_one(f));
      if (earlier.passes.back().size() < frames_per_pass) break;
      if (options.max_noise > 0 && earlier.count() >= 2 &&
          earlier.noise_of_means(options.warmup) < options.max_noise)
        break;
    }
    if (earlier.count() > 0 && earlier.passes.back().size() < frames_per_pass)
      earlier.passes.pop_back();  // the pass a signal cut short
    if (interrupts.signal() && earlier.count() > 0) {
      // Stopped before the recording pass: the finished passes are the result, the last of
      // them recorded with the mean of all. --check and --save-pairs need the recording
      // pass's pipeline state, so those frames have neither.
      const std::vector<FrameStats> last = std::move(earlier.passes.back());
      earlier.passes.pop_back();
      kept_passes = uint32_t(earlier.count() + 1);
      for (size_t k = 0; k < last.size(); ++k) {
        f = range.first + uint32_t(k);
        frames.push_back(last[k]);
        earlier.merge_into(k, f, frames.back());
        if (out) out->append_frame(f, frames.back(), pipeline.memory());
        if (options.frame_lines) {
          progress.clear();
          print_frame_line(f, frames.back());
        }
      }
    } else if (earlier.count() > 0) {
      pipeline.set_topology(source.topology());
    }
    for (f = range.first; f < range.last && !interrupts.signal() && !kept_passes; ++f) {
      frames.push_back(run_one(f));
      earlier.merge_into(frames.size() - 1, f, frames.back());
      if (options.check_every) {
        // After the timed frame. The pass's first frame has no previous one (its swept
        // boxes are its own boxes), so its interval is the frame itself.
        if (f == range.first) contact_rounding.restart();
        contact_rounding.round(positions, vertices);
        if (f == range.first) previous = vertices;
        if ((f - range.first) % options.check_every == 0)
          check_frame_pairs(pipeline, options.oracle(positions), *options.faces, previous, vertices, options.contact,
                            frames.back());
        previous = vertices;
      }
      if (out) {
        out->append_frame(f, frames.back(), pipeline.memory());
        if (options.save_pairs) out->write_pairs(f, pipeline.sorted_pairs());
      }
      if (options.frame_lines) {
        progress.clear();
        print_frame_line(f, frames.back());
      }
    }
  } catch (const std::exception& e) {
    progress.finish();
    if (out)
      out->abandon(summarize_run(frames, options.warmup), pipeline.memory(),
                   "frame " + std::to_string(f) + ": " + e.what());
    if (out) tell_incomplete(*out);
    throw;
  }
  progress.finish();
  print_summary(frames, options.warmup, pipeline.memory(), options.copy_gbps, options.contact, options.list_growth);
  if (!options.accuracy_warning.empty()) print_accuracy_warning(options.accuracy_warning, frames, options.warmup);
  if (const int signal = interrupts.signal()) {
    const std::string why =
        kept_passes ? std::string("interrupted by ") + signal_name(signal) + " after " +
                          std::to_string(kept_passes) + " of " + std::to_string(options.repeat) +
                          " passes (the finished passes kept)"
                    : std::string("interrupted by ") + signal_name(signal) + " after " +
                          std::to_string(frames.size()) + " of " + std::to_string(frames_per_pass) + " frames";
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: %s\n", why.c_str());
    if (out) {
      out->abandon(summarize_run(frames, options.warmup), pipeline.memory(), why);
      tell_incomplete(*out);
    }
    return exit_for_signal(signal);
  }
  // After the summary it qualifies; stored so `compare` can flag the run.
  RunFindings findings;
  findings.noise_warning = noise_warning(measure_noise(frames, options.warmup));
  if (!findings.noise_warning.empty()) std::printf("  warning     %s\n", findings.noise_warning.c_str());
  if (options.input_hash) findings.input_hash = options.input_hash();
  if (result) {
    result->summary = summarize_run(frames, options.warmup);
    result->memory = pipeline.memory();
    result->noise_warning = findings.noise_warning;
    result->input_hash = findings.input_hash;
  }
  if (out) {
    try {
      out->finish(summarize_run(frames, options.warmup), pipeline.memory(), findings);
    } catch (const std::exception&) {
      tell_incomplete(*out);  // e.g. the disk filled while the summary was written
      throw;
    }
    std::printf("results: %s (%llu frames)\n", out->path().c_str(), static_cast<unsigned long long>(out->rows()));
  }
  return kExitOk;
}

}  // namespace cdb
