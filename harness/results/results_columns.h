#pragma once
// The tables of a results file: /frames, one row per frame, /plans, one row per pass and
// frame of a front pipeline saying what the frame ran in that pass (pipeline/plan_record.h),
// and /memory, one row per executor buffer that held memory at the run's peak.
// Each column is one extendible dataset, a row appended at a time, its value read from the
// row by `value`; a new FrameStats field becomes a column by adding one line to
// frame_columns().
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "cdbench/exec/memory.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/plan_step.h"

namespace cdb {

enum class ColumnType { u32, u64, f64, text };

// Text columns are fixed-width (so they compress like the others); a longer value is an
// error, never cut short.
inline constexpr size_t kTextColumnBytes = 64;

using ColumnValue = std::variant<uint64_t, double, std::string>;

template <class Row>
struct TableColumn {
  std::string name;
  ColumnType type;
  std::string description;  // stored with the dataset
  std::function<ColumnValue(const Row&)> value;
};

// One frame as the columns see it: its index in the scene, what the pipeline reported,
// and the executor's memory accounting after it.
struct FrameRow {
  uint32_t frame;
  const FrameStats& stats;
  const MemoryStats& memory;
};

struct PlanRow {
  uint32_t pass;   // 0: the first pass over the frames
  uint32_t frame;  // the frame's index in the scene
  const PlanStep& step;
};

// One buffer at the run's memory peak (MemoryStats::at_peak).
struct MemoryRow {
  const BufferBytes& buffer;
};

using FrameColumn = TableColumn<FrameRow>;
using PlanColumn = TableColumn<PlanRow>;
using MemoryColumn = TableColumn<MemoryRow>;

const std::vector<FrameColumn>& frame_columns();
// /frames columns of a scene that declares queries only (FrameStats::query_pairs): made with
// the first frame that has them; every frame of such a run does.
const std::vector<FrameColumn>& query_pair_columns();
const std::vector<PlanColumn>& plan_columns();
const std::vector<MemoryColumn>& memory_columns();

}  // namespace cdb
