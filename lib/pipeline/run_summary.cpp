#include "cdbench/pipeline/run_summary.h"

#include <algorithm>
#include <cmath>

namespace cdb {

Stat stat_of(std::vector<double> v) {
  Stat s;
  s.count = v.size();
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / double(v.size());
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  s.p95 = v[std::min(v.size() - 1, size_t(std::ceil(0.95 * double(v.size()))) - 1)];
  s.min = v.front();
  return s;
}

RunSummary summarize_run(const std::vector<FrameStats>& frames, uint32_t warmup) {
  RunSummary r;
  r.frames = frames.size();
  if (frames.empty()) return r;
  r.warmup = std::min<size_t>(warmup, frames.size() - 1);
  r.first_ms = frames[0].timing.total_ms;
  r.first_op = frames[0].op;
  std::vector<double> total;
  std::array<std::vector<double>, kPhaseCount> ran;
  double pairs = 0, syncs = 0, floor = 0, pairs_self = 0, pairs_inter = 0;
  r.by_query = frames.back().query_pairs.has_value();
  std::vector<double> noise;
  for (size_t f = r.warmup; f < frames.size(); ++f) {
    total.push_back(frames[f].timing.total_ms);
    noise.push_back(frames[f].timing.total_noise);
    syncs += frames[f].timing.host_syncs;
    floor += double(frames[f].timing.bytes_floor);
    r.host_syncs_max = std::max(r.host_syncs_max, frames[f].timing.host_syncs);
    for (size_t p = 0; p < kPhaseCount; ++p)
      if (frames[f].timing.phase_ms[p] > 0) ran[p].push_back(frames[f].timing.phase_ms[p]);
    pairs += double(frames[f].pairs);
    if (frames[f].query_pairs) {
      pairs_self += double(frames[f].query_pairs->self);
      pairs_inter += double(frames[f].query_pairs->inter);
    }
  }
  for (const auto& f : frames) {
    r.query_reruns += f.timing.query_reruns;
    r.plan_mixed_frames += f.plan_mixed > 0;
    r.decided_refit += f.quality.decision == "refit";
    r.decided_restructure += f.quality.decision == "restructure";
    r.decided_rebuild += f.quality.decision == "rebuild";
    if (f.check.checked) {
      ++r.checked_frames;
      r.recall_min = std::min(r.recall_min, f.check.recall);
      r.precision_min = std::min(r.precision_min, f.check.precision);
      r.missed += f.check.missed;
      r.false_positives += f.check.false_positives;
      r.contacts += f.check.contacts;
      r.discrete_missed_contacts += f.check.discrete_missed_contacts;
      r.checked_pairs += f.pairs;
      r.contact_precision_min = std::min(r.contact_precision_min, f.check.contact_precision);
    }
  }
  if (r.checked_pairs) r.contact_precision = double(r.contacts) / double(r.checked_pairs);
  r.total = stat_of(std::move(total));
  for (size_t p = 0; p < kPhaseCount; ++p) r.phase[p] = stat_of(std::move(ran[p]));
  r.pairs_mean = pairs / double(r.total.count);
  r.pairs_self_mean = pairs_self / double(r.total.count);
  r.pairs_inter_mean = pairs_inter / double(r.total.count);
  r.host_syncs_mean = syncs / double(r.total.count);
  r.bytes_floor_mean = floor / double(r.total.count);
  r.repeats = frames.back().timing.repeats;
  r.noise_median = stat_of(std::move(noise)).median;
  return r;
}

}  // namespace cdb
