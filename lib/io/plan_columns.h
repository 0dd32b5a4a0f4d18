#pragma once
// The plan columns of a results file (/plans/<name>): one row per pass and frame of a front
// pipeline, saying what the frame ran in that pass (pipeline/plan_record.h).
#include <cstdint>
#include <vector>

#include "io/table_column.h"
#include "pipeline/plan_step.h"

namespace cdb {

struct PlanRow {
  uint32_t pass;   // 0: the first pass over the frames
  uint32_t frame;  // the frame's index in the scene
  const PlanStep& step;
};

using PlanColumn = TableColumn<PlanRow>;

const std::vector<PlanColumn>& plan_columns();

}  // namespace cdb
