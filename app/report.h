#pragma once
// Human-readable output of the CLI: per-frame lines, run summary, mismatch reports.
#include <string>
#include <vector>

#include "cdbench/core/pair_set.h"
#include "cdbench/exec/memory.h"
#include "cdbench/narrow/contacts.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

int omp_threads();
void print_frame_line(uint32_t frame, const FrameStats& s);
// copy_gbps: the device's measured copy bandwidth, for the bandwidth floor (0: not shown);
// contact: what --check counted as a contact; list_growth: one line per buffer that grew
// during the run (how often, from which size to which) after the growth count.
void print_summary(const std::vector<FrameStats>& frames, uint32_t warmup, const MemoryStats& mem,
                   double copy_gbps = 0.0, const ContactCheck& contact = {}, bool list_growth = true);
void print_mismatch(const std::string& pipeline, uint32_t frame, const PairSetDiff& d);

}  // namespace cdb
