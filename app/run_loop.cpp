#include "run_loop.h"

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "core/pair_set.h"
#include "interrupt.h"
#include "narrow/contacts.h"
#include "pipeline/run_summary.h"
#include "report.h"

namespace cdb {
namespace {

void check_frame_pairs(Pipeline& pipeline, const std::vector<PrimPair>& expected, const std::vector<Tri>& faces,
                       const std::vector<vec3f>& vertices, FrameStats& s) {
  const std::vector<PrimPair> reported = pipeline.sorted_pairs();
  const PairAccuracy a = pair_accuracy(expected, reported);
  s.checked = true;
  s.recall = a.recall;
  s.precision = a.precision;
  s.missed = a.missed;
  s.false_positives = a.false_positives;
  s.contacts = count_true_contacts(faces, vertices, reported);
  s.contact_precision = contact_precision(s.contacts, reported.size());
}

}  // namespace

int run_frames(Pipeline& pipeline, const FrameSource& source, FrameRange range, ResultsFile* out,
               const RunLoopOptions& options) {
  const InterruptScope interrupts;
  Progress progress(range.last - range.first, options.progress);
  std::vector<FrameStats> frames;
  std::vector<vec3f> vertices;
  uint32_t f = range.first;
  try {
    for (; f < range.last && !interrupts.signal(); ++f) {
      source.frame(f, vertices);
      frames.push_back(pipeline.run_frame(vertices));
      if (options.check_every && (f - range.first) % options.check_every == 0)
        check_frame_pairs(pipeline, options.oracle(vertices), *options.faces, vertices, frames.back());
      if (out) {
        out->append_frame(f, frames.back(), pipeline.memory());
        if (options.save_pairs) out->write_pairs(f, pipeline.sorted_pairs());
      }
      if (options.frame_lines) {
        progress.clear();
        print_frame_line(f, frames.back());
      }
      progress.update(uint32_t(frames.size()));
    }
  } catch (const std::exception& e) {
    progress.finish();
    if (out)
      out->abandon(summarize_run(frames, options.warmup), pipeline.memory(),
                   "frame " + std::to_string(f) + ": " + e.what());
    if (out) std::fprintf(stderr, "cdbench: results (incomplete): %s\n", out->path().c_str());
    throw;
  }
  progress.finish();
  print_summary(frames, options.warmup, pipeline.memory());
  if (const int signal = interrupts.signal()) {
    const std::string why = std::string("interrupted by ") + signal_name(signal) + " after " +
                            std::to_string(frames.size()) + " of " + std::to_string(range.last - range.first) +
                            " frames";
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: %s\n", why.c_str());
    if (out) {
      out->abandon(summarize_run(frames, options.warmup), pipeline.memory(), why);
      std::fprintf(stderr, "cdbench: results (incomplete): %s\n", out->path().c_str());
    }
    return 128 + signal;
  }
  if (out) {
    out->finish(summarize_run(frames, options.warmup), pipeline.memory());
    std::printf("results: %s (%llu frames)\n", out->path().c_str(), static_cast<unsigned long long>(out->rows()));
  }
  return 0;
}

}  // namespace cdb
