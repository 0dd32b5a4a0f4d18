#pragma once
// What one frame of a front pipeline ran, in the words a plan is recorded and replayed in
// (pipeline/plan_record.h): the trees' upkeep, each front query's operation and pipeline
// c's Formula 2 decision and quality inspection. FramePlanner (pipeline/frame_plan.h)
// decides a frame's step or replays a recorded one; FrameStats carries it to the run loop
// and the results file.
#include <array>
#include <cstddef>
#include <optional>

namespace cdb {

// A front pipeline's queries (pipeline/front_pipeline.h): the self fronts of T_D, T_D's
// leaves against T_R, and the self fronts of T_R. Each indexes its counter slot
// (FrontCounters::query) and its operation in a frame's plan (FramePlan::op).
enum class Query { self, inter, rigid_self };
inline constexpr size_t kQueryCount = 3;
inline constexpr Query kQueries[kQueryCount] = {Query::self, Query::inter, Query::rigid_self};

inline const char* query_name(Query q) {
  return q == Query::self ? "self" : q == Query::inter ? "inter" : "rigid_self";
}

// Which queries run in a scene (a split scene runs only those its declared queries need).
using QuerySet = std::array<bool, kQueryCount>;

enum class FrontOp { generate, preserve, update, restructure };

inline const char* front_op_name(FrontOp op) {
  return op == FrontOp::generate   ? "generate"
         : op == FrontOp::preserve ? "preserve"
         : op == FrontOp::update   ? "update"
                                   : "restructure";
}

// Formula 2 (paper §4.2) on the last inspection's candidates, as a share of the leaves.
enum class Formula2 { none, refit, restructure, rebuild };

inline const char* formula2_name(Formula2 d) {
  return d == Formula2::refit ? "refit" : d == Formula2::restructure ? "restructure" : d == Formula2::rebuild ? "rebuild" : "";
}

// The hierarchy's upkeep in a frame: built, refitted, or (--refit-every) left stale; with
// --rebuild-ahead, refitted while a new tree and its fronts are built on a side stream
// (ahead), or replaced by that tree, which is then refitted (adopt); with --update-ahead,
// refitted while T_D's self fronts are updated on the side stream (update-ahead), or
// refitted after those updated fronts replace the current ones (adopt-update).
enum class TreeStep { build, refit, stale, ahead, adopt, update_ahead, adopt_update };

inline const char* tree_step_name(TreeStep t) {
  return t == TreeStep::build          ? "build"
         : t == TreeStep::refit        ? "refit"
         : t == TreeStep::stale        ? "stale"
         : t == TreeStep::ahead        ? "ahead"
         : t == TreeStep::adopt        ? "adopt"
         : t == TreeStep::update_ahead ? "update-ahead"
                                       : "adopt-update";
}

struct PlanStep {
  TreeStep trees = TreeStep::refit;
  // By Query; none for a query that does not run in the scene.
  std::array<std::optional<FrontOp>, kQueryCount> ops{};
  Formula2 decision = Formula2::none;  // taken at the frame's start on the last inspection
  bool inspect = false;                // pipeline c inspected T_D's quality after the frame's operations
  bool probe = false;                  // a preserve that counted what an update would make (FrontQuery::update_yield)

  const std::optional<FrontOp>& op(Query q) const { return ops[size_t(q)]; }
  std::optional<FrontOp>& op(Query q) { return ops[size_t(q)]; }
  bool runs(FrontOp o) const {
    for (const auto& op : ops)
      if (op == o) return true;
    return false;
  }
  bool operator==(const PlanStep&) const = default;
};

}  // namespace cdb
