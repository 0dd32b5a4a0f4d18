#include "plan_table.h"

#include <cstdio>

#include "cdbench/core/error.h"
#include "exit_codes.h"
#include "harness/plans/plan_source.h"
#include "cdbench/pipeline/plan_record.h"

namespace cdb {
namespace {

// How the first pass planned: --front-cycle auto or K, as the file's options say.
std::string own_planning(const ResultsOverview& r) {
  const auto cycle = r.options.find("front-cycle");
  if (cycle == r.options.end() || (cycle->is_string() && cycle->get<std::string>() == "auto")) return "adaptive";
  return "cycle " + (cycle->is_string() ? cycle->get<std::string>() : cycle->dump());
}

}  // namespace

std::vector<std::string> plan_table_header() {
  return {"file", "pipeline", "pass", "planned", "frames by operation", "same as pass 0"};
}

std::vector<std::vector<std::string>> plan_rows(const ResultsOverview& r, const ResultsPlans& plans) {
  std::vector<std::vector<std::string>> rows;
  for (size_t p = 0; p < plans.passes.size(); ++p) {
    const RecordedPlan& plan = plans.passes[p];
    const std::string planned = !r.plan_source.empty()                ? "replay of " + r.plan_source
                                : p > 0 && r.repeat_plan == "replay" ? "replay of pass 0"
                                                                      : own_planning(r);
    std::string same;
    if (p > 0) {
      const std::vector<uint32_t> differ = frames_that_differ(plans.passes[0], plan);
      same = differ.empty() ? "yes" : "no: frames " + frame_list_text(differ);
    }
    rows.push_back({r.path, plans.pipeline, std::to_string(p), planned, plan_outline(plan), same});
  }
  return rows;
}

std::string plan_summary(const ResultsOverview& r) {
  if (!r.has_plans) return "";
  if (!r.plan_source.empty()) return "replayed " + r.plan_source;
  if (!(r.repeats > 1)) return "one pass";
  if (r.repeat_plan == "replay") return "pass 0 replayed";
  return r.plan_mixed_frames ? "free, " + std::to_string(r.plan_mixed_frames) + " frames mixed" : "free, passes agree";
}

int print_plan_file(const std::vector<std::string>& files) {
  if (files.size() != 1)
    fail_usage("report --plan: one results file or plan file, not " + std::to_string(files.size()));
  const RecordedPlan plan = load_plan(files[0], "");
  std::printf("%s", format_plan(plan, {"recorded: " + plan.source, plan_outline(plan),
                                       "replay: cdbench run ... --front-cycle FILE (docs/usage.md \"Plans\")"})
                        .c_str());
  return kExitOk;
}

}  // namespace cdb
