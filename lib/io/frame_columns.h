#pragma once
// The per-frame columns of a results file (/frames/<name>), as one table over FrameStats.
// A new FrameStats field becomes a column by adding one line to frame_columns().
#include <cstdint>
#include <vector>

#include "exec/memory.h"
#include "io/table_column.h"
#include "pipeline/pipeline.h"

namespace cdb {

// One frame as the columns see it: its index in the scene, what the pipeline reported,
// and the executor's memory accounting after it.
struct FrameRow {
  uint32_t frame;
  const FrameStats& stats;
  const MemoryStats& memory;
};

using FrameColumn = TableColumn<FrameRow>;

const std::vector<FrameColumn>& frame_columns();

}  // namespace cdb
