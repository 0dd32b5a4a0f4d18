#pragma once
// Where a replayed front plan comes from (`run --front-cycle FILE`, `report --plan`): a
// plan file (pipeline/plan_record.h), or one pass of a results file's /plans, named
// FILE.h5 (its first pass), FILE.h5:PIPELINE or FILE.h5:PIPELINE:PASS. A results file is
// told from a plan file by its HDF5 signature, not by its name.
#include <string>

#include "cdbench/pipeline/plan_record.h"

namespace cdb {

// `pipeline`: the pipeline that replays the plan ("" for any). A results file named
// without PIPELINE must hold that pipeline's plans; naming PIPELINE replays another
// pipeline's (the file must hold that one's). Throws Error naming the file and, for a plan
// file, the line and field of what it cannot read.
RecordedPlan load_plan(const std::string& spec, const std::string& pipeline);

}  // namespace cdb
