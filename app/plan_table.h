#pragma once
// What `cdbench report` shows of the front plans a results file records: per file and
// pass, the frames that built, updated, generated and restructured, and whether the pass
// ran pass 0's plan; and `report --plan`, one pass's plan as a plan file for
// `run --front-cycle FILE`.
#include <string>
#include <vector>

#include "harness/results/results_reader.h"

namespace cdb {

// The columns of plan_rows: file, pipeline, pass, how it was planned, its frames by
// operation, and whether it ran pass 0's plan.
std::vector<std::string> plan_table_header();
// One row per pass of `plans`, the plans of the file `overview` describes.
std::vector<std::vector<std::string>> plan_rows(const ResultsOverview& overview, const ResultsPlans& plans);

// How a file's passes were planned, for report's table: "replayed FILE", "pass 0 replayed",
// "free, passes agree", "free, 3 frames mixed", "one pass".
std::string plan_summary(const ResultsOverview& overview);

// report --plan SPEC (a results file FILE.h5[:PIPELINE[:PASS]], or a plan file to check):
// the plan file on stdout. `files`: the one SPEC given.
int print_plan_file(const std::vector<std::string>& files);

}  // namespace cdb
