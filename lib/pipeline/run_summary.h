#pragma once
// Summary statistics of a run's frames: what the CLI prints and the results file stores,
// computed once so the two always agree.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cdbench/core/phase.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

struct Stat {
  double mean = 0, median = 0, p95 = 0, min = 0;
  size_t count = 0;  // values the statistics are over; 0 leaves the others at 0
};

// Mean, median, 95th percentile (nearest rank) and minimum.
Stat stat_of(std::vector<double> values);

struct RunSummary {
  size_t frames = 0;     // frames run
  size_t warmup = 0;     // frames left out of the statistics (never all of them)
  double first_ms = 0;   // the first frame's total, apart: it builds
  std::string first_op;
  Stat total;            // t_total_ms over the measured frames
  // Per phase over the measured frames where it ran (a front update runs one frame in a
  // cycle, so zeros would drag its mean down).
  std::array<Stat, kPhaseCount> phase{};
  double pairs_mean = 0;
  // Scenes with declared queries (FrameStats::query_pairs): the mean pairs of each kind.
  bool by_query = false;
  double pairs_self_mean = 0, pairs_inter_mean = 0;
  // --repeat: passes each frame's times are the mean of, and the median over the measured
  // frames of their relative standard deviation (the noise reported beside every time).
  uint32_t repeats = 1;
  double noise_median = 0;
  // Host-device synchronizations per measured frame (target: 1).
  double host_syncs_mean = 0;
  uint32_t host_syncs_max = 0;
  double bytes_floor_mean = 0;  // per measured frame; see FrameTiming::bytes_floor
  uint32_t query_reruns = 0;  // over all frames, warm-up included
  // --repeat: frames whose passes ran different plan steps (FrameStats::plan_mixed), warm-up
  // included.
  size_t plan_mixed_frames = 0;
  // --warmup-ms: frames run untimed before the measured passes (set by the run loop).
  uint64_t warmup_frames = 0;
  // Formula 2 decisions of pipeline c over all frames.
  size_t decided_refit = 0, decided_restructure = 0, decided_rebuild = 0;
  // --check over all checked frames, warm-up included.
  size_t checked_frames = 0;
  double recall_min = 1.0, precision_min = 1.0;
  uint64_t missed = 0, false_positives = 0;
  // True contacts among the checked frames' reported pairs: summed, their pooled share
  // (contacts / pairs over all checked frames; 1 with no pairs) and the lowest frame's share.
  uint64_t contacts = 0, checked_pairs = 0;
  double contact_precision = 1.0, contact_precision_min = 1.0;
  // Contacts of the frame intervals that discrete boxes miss, summed over the checked frames.
  uint64_t discrete_missed_contacts = 0;
};

RunSummary summarize_run(const std::vector<FrameStats>& frames, uint32_t warmup);

}  // namespace cdb
