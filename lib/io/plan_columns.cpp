#include "io/plan_columns.h"

#include <string>

namespace cdb {

const std::vector<PlanColumn>& plan_columns() {
  static const std::vector<PlanColumn> columns = [] {
    using T = ColumnType;
    using R = const PlanRow&;
    std::vector<PlanColumn> c = {
        {"pass", T::u32, "--repeat: the pass over the frames (0: the first)", [](R r) -> ColumnValue { return uint64_t(r.pass); }},
        {"frame", T::u32, "frame index in the scene", [](R r) -> ColumnValue { return uint64_t(r.frame); }},
        {"trees", T::text, "the hierarchy: build, refit or stale (--refit-every kept its boxes)", [](R r) -> ColumnValue { return std::string(tree_step_name(r.step.trees)); }},
    };
    for (Query q : kQueries)
      c.push_back({query_name(q), T::text,
                   std::string("the ") + query_name(q) + " query's front operation: generate, preserve, update or restructure (empty: the query does not run in the scene)",
                   [q](R r) -> ColumnValue { return std::string(r.step.op(q) ? front_op_name(*r.step.op(q)) : ""); }});
    c.push_back({"decision", T::text, "pipeline c: the Formula 2 decision taken at the frame's start (refit, restructure, rebuild; empty: none)", [](R r) -> ColumnValue { return std::string(formula2_name(r.step.decision)); }});
    c.push_back({"inspect", T::u32, "pipeline c: 1 when the frame inspected the tree's quality", [](R r) -> ColumnValue { return uint64_t(r.step.inspect); }});
    return c;
  }();
  return columns;
}

}  // namespace cdb
