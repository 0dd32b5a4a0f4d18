#pragma once
// The per-frame columns of a results file (/frames/<name>), as one table over FrameStats.
// A new FrameStats field becomes a column by adding one line to frame_columns().
#include <cstdint>
#include <functional>
#include <string>
#include <variant>
#include <vector>

#include "exec/memory.h"
#include "pipeline/pipeline.h"

namespace cdb {

// One frame as the columns see it: its index in the scene, what the pipeline reported,
// and the executor's memory accounting after it.
struct FrameRow {
  uint32_t frame;
  const FrameStats& stats;
  const MemoryStats& memory;
};

enum class ColumnType { u32, u64, f64, text };

// Text columns are fixed-width (so they compress like the others); a longer value is an
// error, never cut short.
inline constexpr size_t kTextColumnBytes = 64;

using ColumnValue = std::variant<uint64_t, double, std::string>;

struct FrameColumn {
  std::string name;
  ColumnType type;
  std::string description;  // stored with the dataset
  std::function<ColumnValue(const FrameRow&)> value;
};

const std::vector<FrameColumn>& frame_columns();

}  // namespace cdb
