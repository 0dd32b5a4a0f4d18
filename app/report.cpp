#include "report.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace cdb {

int omp_threads() { return omp_get_max_threads(); }

void print_frame_line(uint32_t frame, const FrameStats& s) {
  std::printf("frame %4u  %-15s %9.3f ms  pairs %10llu", frame, s.op.c_str(), s.total_ms,
              static_cast<unsigned long long>(s.pairs));
  if (s.front_internal + s.front_external)
    std::printf("  front %llu+%llu  Q %.3f", static_cast<unsigned long long>(s.front_internal),
                static_cast<unsigned long long>(s.front_external), s.q_root);
  for (size_t p = 1; p < kPhaseCount; ++p)
    if (s.phase_ms[p] > 0) std::printf("  %s %.3f", kPhaseNames[p], s.phase_ms[p]);
  if (!s.decision.empty()) std::printf("  decision %s", s.decision.c_str());
  if (s.candidates)
    std::printf("  candidates %llu (%llu leaves, mean Q %.3f)", static_cast<unsigned long long>(s.candidates),
                static_cast<unsigned long long>(s.candidate_leaves), s.q_candidates);
  if (s.query_reruns) std::printf("  (a buffer grew, re-ran %u)", s.query_reruns);
  std::printf("\n");
}

namespace {
struct Stat {
  double mean = 0, median = 0, p95 = 0, min = 0;
};
Stat stat_of(std::vector<double> v) {
  Stat s;
  if (v.empty()) return s;
  std::sort(v.begin(), v.end());
  double sum = 0;
  for (double x : v) sum += x;
  s.mean = sum / v.size();
  s.median = v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
  s.p95 = v[std::min(v.size() - 1, size_t(std::ceil(0.95 * v.size())) - 1)];
  s.min = v.front();
  return s;
}
}  // namespace

void print_summary(const std::vector<FrameStats>& frames, uint32_t warmup, const MemoryStats& mem) {
  if (frames.empty()) return;
  const size_t skip = std::min<size_t>(warmup, frames.size() - 1);
  std::vector<double> total;
  std::vector<std::vector<double>> phase(kPhaseCount);
  double pairs = 0;
  uint32_t reruns = 0;
  for (size_t f = skip; f < frames.size(); ++f) {
    total.push_back(frames[f].total_ms);
    for (size_t p = 0; p < kPhaseCount; ++p) phase[p].push_back(frames[f].phase_ms[p]);
    pairs += double(frames[f].pairs);
  }
  size_t decided[3] = {0, 0, 0};  // refit, restructure, rebuild
  for (const auto& f : frames) {
    reruns += f.query_reruns;
    decided[0] += f.decision == "refit";
    decided[1] += f.decision == "restructure";
    decided[2] += f.decision == "rebuild";
  }
  const Stat t = stat_of(total);
  std::printf("summary: %zu frames measured (first %zu left out as warm-up)\n", total.size(), skip);
  std::printf("  first frame %.3f ms (%s)\n", frames[0].total_ms, frames[0].op.c_str());
  std::printf("  per frame   mean %.3f  median %.3f  p95 %.3f  min %.3f ms (upload excluded)\n",
              t.mean, t.median, t.p95, t.min);
  // Per phase, over the frames where it ran (a front update runs one frame in a cycle).
  for (size_t p = 0; p < kPhaseCount; ++p) {
    std::vector<double> ran;
    for (double ms : phase[p])
      if (ms > 0) ran.push_back(ms);
    if (ran.empty()) continue;
    const Stat s = stat_of(ran);
    std::printf("  %-11s mean %.3f  median %.3f  p95 %.3f ms  (%zu frames)\n", kPhaseNames[p], s.mean,
                s.median, s.p95, ran.size());
  }
  std::printf("  pairs       mean %.0f per frame\n", pairs / double(total.size()));
  const FrameStats& last = frames.back();
  if (last.front_internal + last.front_external)
    std::printf("  front       %llu internal + %llu external nodes at the end, Q(root) %.3f\n",
                static_cast<unsigned long long>(last.front_internal),
                static_cast<unsigned long long>(last.front_external), last.q_root);
  if (decided[0] + decided[1] + decided[2])
    std::printf("  formula 2   %zu refit, %zu restructure, %zu rebuild decisions\n", decided[0],
                decided[1], decided[2]);
  std::printf("  memory      peak %.2f MiB, %zu allocations, %zu growths, %u query re-runs\n",
              double(mem.peak_bytes) / (1 << 20), mem.allocations, mem.growths, reruns);
}

void print_mismatch(const std::string& pipeline, uint32_t frame, const PairSetDiff& d) {
  std::printf("  MISMATCH %s frame %u: expected %llu pairs, got %llu; %llu missing, %llu unexpected\n",
              pipeline.c_str(), frame, static_cast<unsigned long long>(d.expected),
              static_cast<unsigned long long>(d.actual),
              static_cast<unsigned long long>(d.missing_count),
              static_cast<unsigned long long>(d.unexpected_count));
  for (const auto& p : d.missing) std::printf("    missing (%u, %u)\n", p.a, p.b);
  for (const auto& p : d.unexpected) std::printf("    unexpected (%u, %u)\n", p.a, p.b);
}

}  // namespace cdb
