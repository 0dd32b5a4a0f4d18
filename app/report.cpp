#include "report.h"

#include <omp.h>

#include <cstdio>
#include <string>
#include <vector>

#include "cdbench/pipeline/run_summary.h"

namespace cdb {

int omp_threads() { return omp_get_max_threads(); }

void print_frame_line(uint32_t frame, const FrameStats& s) {
  std::printf("frame %4u  %-15s %9.3f ms", frame, s.op.c_str(), s.timing.total_ms);
  if (s.timing.repeats > 1) std::printf(" ±%.1f%%", 100.0 * s.timing.total_noise);
  std::printf("  pairs %10llu", static_cast<unsigned long long>(s.pairs));
  if (s.fronts.internal + s.fronts.external)
    std::printf("  front %llu+%llu  Q %.3f", static_cast<unsigned long long>(s.fronts.internal),
                static_cast<unsigned long long>(s.fronts.external), s.quality.q_root);
  if (s.fronts.inter) std::printf("  inter front %llu", static_cast<unsigned long long>(s.fronts.inter));
  if (s.fronts.rigid) std::printf("  rigid front %llu", static_cast<unsigned long long>(s.fronts.rigid));
  for (size_t p = 1; p < kPhaseCount; ++p)
    if (s.timing.phase_ms[p] > 0) std::printf("  %s %.3f", kPhaseNames[p], s.timing.phase_ms[p]);
  if (!s.quality.decision.empty()) std::printf("  decision %s", s.quality.decision.c_str());
  if (s.quality.candidates)
    std::printf("  candidates %llu (%llu leaves, mean Q %.3f)", static_cast<unsigned long long>(s.quality.candidates),
                static_cast<unsigned long long>(s.quality.candidate_leaves), s.quality.q_candidates);
  if (s.check.checked)
    std::printf("  check recall %.6f precision %.6f contacts %llu (%.6f) discrete-missed %llu", s.check.recall, s.check.precision,
                static_cast<unsigned long long>(s.check.contacts), s.check.contact_precision,
                static_cast<unsigned long long>(s.check.discrete_missed_contacts));
  if (s.timing.query_reruns) std::printf("  (a buffer grew, re-ran %u)", s.timing.query_reruns);
  if (s.timing.ahead_ms > 0) std::printf("  (adopted a build that ran %.3f ms beside earlier frames)", s.timing.ahead_ms);
  std::printf("\n");
}

namespace {

// One line per buffer that grew; the buffers of one structure (front_internal.prim,
// front_internal.node, ...) that grew alike share a line.
void print_growth(const std::vector<BufferGrowth>& grown) {
  std::vector<bool> printed(grown.size(), false);
  for (size_t i = 0; i < grown.size(); ++i) {
    if (printed[i]) continue;
    const BufferGrowth& g = grown[i];
    const size_t dot = g.buffer.rfind('.');
    const std::string owner = dot == std::string::npos ? "" : g.buffer.substr(0, dot + 1);
    std::string names = g.buffer.substr(owner.size());
    size_t alike = 1;
    for (size_t j = i + 1; j < grown.size() && !owner.empty(); ++j) {
      const BufferGrowth& h = grown[j];
      const bool same_owner =
          h.buffer.compare(0, owner.size(), owner) == 0 && h.buffer.find('.', owner.size()) == std::string::npos;
      if (printed[j] || !same_owner || h.times != g.times || h.first_count != g.first_count ||
          h.last_count != g.last_count)
        continue;
      names.append(",").append(h.buffer, owner.size());
      printed[j] = true;
      ++alike;
    }
    const std::string what = alike > 1 ? std::string(owner).append("{").append(names).append("}") : g.buffer;
    std::printf("  grew        %s %zu time%s, %zu to %zu\n", what.c_str(), g.times, g.times == 1 ? "" : "s",
                g.first_count, g.last_count);
  }
}

}  // namespace

void print_summary(const std::vector<FrameStats>& frames, uint32_t warmup, const MemoryStats& mem,
                   double copy_gbps, const ContactCheck& contact, bool list_growth) {
  if (frames.empty()) return;
  const RunSummary r = summarize_run(frames, warmup);
  std::printf("summary: %zu frames measured (first %zu left out as warm-up)\n", r.total.count, r.warmup);
  std::printf("  first frame %.3f ms (%s)\n", r.first_ms, r.first_op.c_str());
  std::printf("  per frame   mean %.3f  median %.3f  p95 %.3f  min %.3f ms (upload excluded)\n",
              r.total.mean, r.total.median, r.total.p95, r.total.min);
  if (r.repeats > 1)
    std::printf("  noise       %.2f%% (median over frames of the relative std. dev. over %u passes)\n",
                100.0 * r.noise_median, r.repeats);
  std::printf("  syncs       %.2f per frame, at most %u (host-device synchronizations)\n",
              r.host_syncs_mean, r.host_syncs_max);
  if (copy_gbps > 0 && r.total.mean > 0) {
    const double floor_ms = r.bytes_floor_mean / (copy_gbps * 1e9) * 1e3;
    std::printf("  floor       %.4f ms per frame (%.1f MB at %.0f GB/s copy bandwidth): %.1fx above\n",
                floor_ms, r.bytes_floor_mean / 1e6, copy_gbps, r.total.mean / floor_ms);
  }
  for (size_t p = 0; p < kPhaseCount; ++p) {
    const Stat& s = r.phase[p];
    if (s.count == 0) continue;
    std::printf("  %-11s mean %.3f  median %.3f  p95 %.3f ms  (%zu frames)\n", kPhaseNames[p], s.mean,
                s.median, s.p95, s.count);
  }
  if (r.by_query)
    std::printf("  pairs       mean %.0f per frame (self %.0f, inter %.0f)\n", r.pairs_mean, r.pairs_self_mean,
                r.pairs_inter_mean);
  else
    std::printf("  pairs       mean %.0f per frame\n", r.pairs_mean);
  const FrameStats& last = frames.back();
  if (last.fronts.internal + last.fronts.external)
    std::printf("  front       %llu internal + %llu external nodes at the end, Q(root) %.3f\n",
                static_cast<unsigned long long>(last.fronts.internal),
                static_cast<unsigned long long>(last.fronts.external), last.quality.q_root);
  if (last.fronts.inter + last.fronts.rigid)
    std::printf("  fronts      %llu inter (deformable vs rigid tree) + %llu rigid self nodes at the end\n",
                static_cast<unsigned long long>(last.fronts.inter), static_cast<unsigned long long>(last.fronts.rigid));
  if (r.checked_frames)
    std::printf("  check       %zu frames against the oracle: recall min %.6f, precision min %.6f, "
                "%llu missed, %llu false positives\n",
                r.checked_frames, r.recall_min, r.precision_min,
                static_cast<unsigned long long>(r.missed), static_cast<unsigned long long>(r.false_positives));
  if (r.checked_frames) {
    if (contact.distance > 0)
      std::printf("  contacts    %llu of %llu checked pairs lie within %.9g: contact precision %.6f, min %.6f\n",
                  static_cast<unsigned long long>(r.contacts), static_cast<unsigned long long>(r.checked_pairs),
                  double(contact.distance), r.contact_precision, r.contact_precision_min);
    else
      std::printf("  contacts    %llu of %llu checked pairs truly intersect: contact precision %.6f, min %.6f\n",
                  static_cast<unsigned long long>(r.contacts), static_cast<unsigned long long>(r.checked_pairs),
                  r.contact_precision, r.contact_precision_min);
    std::printf("  interval    %llu contacts missed by discrete boxes (reported pairs beyond the discrete oracle "
                "within %.9g at one of %u sampled times since the previous frame; a lower bound)\n",
                static_cast<unsigned long long>(r.discrete_missed_contacts), double(contact.distance),
                contact.substeps + 1);
  }
  if (r.decided_refit + r.decided_restructure + r.decided_rebuild)
    std::printf("  formula 2   %zu refit, %zu restructure, %zu rebuild decisions\n", r.decided_refit,
                r.decided_restructure, r.decided_rebuild);
  std::printf("  memory      peak %.2f MiB, %zu allocations, %zu growths, %u query re-runs\n",
              double(mem.peak_bytes) / (1 << 20), mem.allocations, mem.growths, r.query_reruns);
  if (list_growth) print_growth(mem.grown);
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
