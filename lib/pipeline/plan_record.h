#pragma once
// The plan one pass of a front pipeline ran, frame by frame: recorded by the run (the
// results file's /plans), written as a plan file (`cdbench report --plan`), read back and
// replayed (`run --front-cycle FILE`, FramePlanner::replay), so that passes, runs and
// binaries can run the same operations at the same frames. A plan file is text: the header
// "cdbench-plan 1", then one line per frame, e.g. "2 refit self=update inspect" (the
// fields are in docs/usage.md "Plans").
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "cdbench/pipeline/plan_step.h"

namespace cdb {

inline constexpr const char* kPlanFileHeader = "cdbench-plan 1";

struct PlannedFrame {
  uint32_t frame = 0;  // the frame's index in the scene
  PlanStep step;
  size_t line = 0;  // its line in the plan file it was read from (0: not read from one)
};

struct RecordedPlan {
  // Where it came from, for messages: a plan file's path, or "r.h5 (pipeline c, pass 0)".
  std::string source;
  std::vector<PlannedFrame> frames;  // consecutive frames, in order
  // Whether the steps say which frames probed; plans without (recorded before they did, or
  // written naming no probe) probe on the preserve before each update.
  bool records_probes = false;

  // The k-th frame for a message: "plan.txt line 5 (frame 4)", or "r.h5 (pipeline c, pass
  // 0) frame 4".
  std::string where(size_t k) const;
};

// A frame's fields after its index, as a plan file and the results file hold them:
// "refit self=update inspect".
std::string format_plan_step(const PlanStep& step);
// Parses what format_plan_step wrote; throws Error "WHERE field N ('TEXT'): why", fields
// counted from `first_field`.
PlanStep parse_plan_step(const std::string& fields, const std::string& where, size_t first_field = 1);

// The plan file: the header, each of `comments` as a "# " line, one line per frame.
std::string format_plan(const RecordedPlan& plan, const std::vector<std::string>& comments = {});
// A plan file's text; `source` names it in errors, which say the line and the field.
RecordedPlan parse_plan(const std::string& text, const std::string& source);

// The frames as a compact list: "9,10,20-22,37" (runs of three or more as ranges), "—"
// when there are none.
std::string frame_list_text(const std::vector<uint32_t>& frames);
// The frames that built the trees, updated, generated (on a refitted tree: a maintenance,
// not a build) and restructured, and any left stale:
// "build: 0; update: 9,10,20-22,37; generate: —; restructure: —".
std::string plan_outline(const RecordedPlan& plan);
// The frames whose steps differ between two passes over the same frames (and the frames
// only one of them ran).
std::vector<uint32_t> frames_that_differ(const RecordedPlan& a, const RecordedPlan& b);

// Before a replay, each throwing Error naming the plan, the frame and what does not fit:
// the run's frames [first, last) are the plan's first frames, one for one.
void check_plan_frames(const RecordedPlan& plan, uint32_t first, uint32_t last);

// What a front pipeline can replay (FramePlanner checks a plan against its own).
struct ReplayTarget {
  bool restructures = false;         // pipeline c: inspections, Formula 2, restructures
  bool rebuild_every_frame = false;  // never keeps stale boxes
  uint32_t refit_every = 1;          // --refit-every: which frames keep stale boxes
  bool builds_ahead = false;         // --rebuild-ahead: builds on a side stream (ahead, adopt)
};
// Every step can run on the target: the first frame builds, a build generates every
// query's fronts, a restructure (self only, pipeline c) follows an inspection and
// regenerates the cross fronts, decisions and inspections only in c, and frames stale
// exactly where the target's --refit-every keeps stale boxes; a build ahead only on a target
// that builds ahead, each adopted once before the next, and every front preserved from the
// ahead frame to its adopt frame.
void check_plan_steps(const RecordedPlan& plan, const ReplayTarget& target);
// Every step gives an operation to exactly the queries that run in the scene.
void check_plan_queries(const RecordedPlan& plan, const QuerySet& running);

}  // namespace cdb
