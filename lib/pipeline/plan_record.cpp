#include "cdbench/pipeline/plan_record.h"

#include <algorithm>
#include <charconv>
#include <optional>
#include <sstream>

#include "cdbench/core/error.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {
namespace {

template <class T, size_t N>
std::optional<T> named(const std::string& word, const T (&values)[N], const char* (*name)(T)) {
  for (T v : values)
    if (word == name(v)) return v;
  return std::nullopt;
}

constexpr TreeStep kTreeSteps[] = {TreeStep::build, TreeStep::refit,        TreeStep::stale,       TreeStep::ahead,
                                    TreeStep::adopt, TreeStep::update_ahead, TreeStep::adopt_update};
constexpr const char* kTreeStepList = "build, refit, stale, ahead, adopt, update-ahead or adopt-update";
constexpr FrontOp kFrontOps[] = {FrontOp::generate, FrontOp::preserve, FrontOp::update, FrontOp::restructure};
constexpr Formula2 kDecisions[] = {Formula2::refit, Formula2::restructure, Formula2::rebuild};

// What a step that launches side work calls it in messages, and with its article.
const char* side_work_name(TreeStep t) { return t == TreeStep::update_ahead ? "update ahead" : "build ahead"; }
std::string a_side_work(TreeStep t) { return (t == TreeStep::update_ahead ? "an " : "a ") + std::string(side_work_name(t)); }

std::vector<std::string> split_fields(const std::string& text) {
  std::vector<std::string> fields;
  std::istringstream in(text);
  for (std::string f; in >> f;) fields.push_back(f);
  return fields;
}

// A line as a message may quote it: at most 40 characters, anything unprintable as '?'.
std::string quoted(const std::string& s) {
  std::string q;
  for (char c : s.substr(0, 40)) q += (c >= 32 && c < 127) ? c : '?';
  return s.size() > 40 ? q + "..." : q;
}

std::optional<uint32_t> frame_number(const std::string& s) {
  uint32_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

std::string RecordedPlan::where(size_t k) const {
  const PlannedFrame& f = frames[k];
  return f.line ? source + " line " + std::to_string(f.line) + " (frame " + std::to_string(f.frame) + ")"
                : source + " frame " + std::to_string(f.frame);
}

std::string format_plan_step(const PlanStep& s) {
  std::string text = tree_step_name(s.trees);
  for (Query q : kQueries)
    if (s.op(q)) text += std::string(" ") + query_name(q) + "=" + front_op_name(*s.op(q));
  if (s.decision != Formula2::none) text += std::string(" decision=") + formula2_name(s.decision);
  if (s.inspect) text += " inspect";
  if (s.probe) text += " probe";
  return text;
}

PlanStep parse_plan_step(const std::string& text, const std::string& where, size_t first_field) {
  const std::vector<std::string> fields = split_fields(text);
  PlanStep s;
  bool decided = false;
  for (size_t i = 0; i < fields.size(); ++i) {
    const std::string& f = fields[i];
    const std::string at = where + " field " + std::to_string(first_field + i) + " ('" + quoted(f) + "'): ";
    if (i == 0) {
      const std::optional<TreeStep> trees = named(f, kTreeSteps, tree_step_name);
      if (!trees) fail(at + "expected the trees' step: " + kTreeStepList);
      s.trees = *trees;
      continue;
    }
    if (f == "inspect" || f == "probe") {
      bool& flag = f == "inspect" ? s.inspect : s.probe;
      if (flag) fail(at + f + " given twice");
      flag = true;
      continue;
    }
    const size_t eq = f.find('=');
    const std::string key = f.substr(0, eq), value = eq == std::string::npos ? "" : f.substr(eq + 1);
    if (eq == std::string::npos)
      fail(at + "expected QUERY=OP (self, inter, rigid_self), decision=D, inspect or probe");
    if (key == "decision") {
      const std::optional<Formula2> d = named(value, kDecisions, formula2_name);
      if (!d) fail(at + "unknown decision '" + quoted(value) + "' (refit, restructure, rebuild)");
      if (decided) fail(at + "decision given twice");
      s.decision = *d;
      decided = true;
      continue;
    }
    const std::optional<Query> q = named(key, kQueries, query_name);
    if (!q) fail(at + "unknown query '" + quoted(key) + "' (self, inter, rigid_self)");
    const std::optional<FrontOp> op = named(value, kFrontOps, front_op_name);
    if (!op) fail(at + "unknown operation '" + quoted(value) + "' (generate, preserve, update, restructure)");
    if (s.op(*q)) fail(at + "query " + key + " given twice");
    s.op(*q) = *op;
  }
  if (fields.empty())
    fail(where + " field " + std::to_string(first_field) + ": missing the trees' step (" + kTreeStepList + ")");
  return s;
}

std::string format_plan(const RecordedPlan& plan, const std::vector<std::string>& comments) {
  std::string text = std::string(kPlanFileHeader) + "\n";
  for (const std::string& c : comments) text += "# " + c + "\n";
  for (const PlannedFrame& f : plan.frames) text += std::to_string(f.frame) + " " + format_plan_step(f.step) + "\n";
  return text;
}

RecordedPlan parse_plan(const std::string& text, const std::string& source) {
  RecordedPlan plan;
  plan.source = source;
  std::istringstream in(text);
  bool header = false;
  size_t number = 0;
  for (std::string line; std::getline(in, line);) {
    ++number;
    const std::string content = line.substr(0, line.find('#'));
    const std::vector<std::string> fields = split_fields(content);
    if (fields.empty()) continue;
    const std::string at = source + " line " + std::to_string(number);
    if (!header) {
      if (fields.size() == 2 && fields[0] == "cdbench-plan" && fields[1] != "1")
        fail(at + ": plan format version " + quoted(fields[1]) + "; this cdbench reads version 1");
      if (fields.size() != 2 || fields[0] + " " + fields[1] != kPlanFileHeader)
        fail(at + ": not a cdbench plan file: expected the header '" + kPlanFileHeader + "', got '" + quoted(line) +
             "'");
      header = true;
      continue;
    }
    const std::optional<uint32_t> frame = frame_number(fields[0]);
    if (!frame) fail(at + " field 1 ('" + quoted(fields[0]) + "'): expected the frame's index, a whole number");
    if (!plan.frames.empty() && *frame != plan.frames.back().frame + 1)
      fail(at + " field 1 ('" + fields[0] + "'): frame " + std::to_string(*frame) + " after frame " +
           std::to_string(plan.frames.back().frame) + ": a plan lists consecutive frames");
    const size_t rest = content.find(fields[0]) + fields[0].size();
    plan.frames.push_back({*frame, parse_plan_step(content.substr(rest), at, 2), number});
    plan.records_probes = plan.records_probes || plan.frames.back().step.probe;
  }
  if (!header) fail(source + ": not a cdbench plan file: empty (expected the header '" + kPlanFileHeader + "')");
  if (plan.frames.empty()) fail(source + ": the plan has no frames (one line per frame after the header)");
  return plan;
}

std::string frame_list_text(const std::vector<uint32_t>& frames) {
  if (frames.empty()) return "—";
  std::string text;
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    if (!text.empty()) text += ',';
    text += std::to_string(frames[i]);
    // Runs of three or more as a range.
    if (j > i) text.append(1, j - i >= 2 ? '-' : ',').append(std::to_string(frames[j]));
    i = j + 1;
  }
  return text;
}

std::string plan_outline(const RecordedPlan& plan) {
  std::vector<uint32_t> build, update, generate, restructure, stale, ahead, adopt, update_ahead, adopt_update;
  for (const PlannedFrame& f : plan.frames) {
    const PlanStep& s = f.step;
    if (s.trees == TreeStep::build) build.push_back(f.frame);
    if (s.trees == TreeStep::ahead) ahead.push_back(f.frame);
    if (s.trees == TreeStep::adopt) adopt.push_back(f.frame);
    if (s.trees == TreeStep::update_ahead) update_ahead.push_back(f.frame);
    if (s.trees == TreeStep::adopt_update) adopt_update.push_back(f.frame);
    if (s.trees == TreeStep::stale) stale.push_back(f.frame);
    if (s.runs(FrontOp::update)) update.push_back(f.frame);
    // A build generates every front, and a restructure regenerates the cross fronts: those
    // generates are part of the build and the restructure.
    if (s.runs(FrontOp::generate) && s.trees != TreeStep::build && !s.runs(FrontOp::restructure))
      generate.push_back(f.frame);
    if (s.runs(FrontOp::restructure)) restructure.push_back(f.frame);
  }
  std::string text = "build: " + frame_list_text(build) + "; update: " + frame_list_text(update) +
                     "; generate: " + frame_list_text(generate) + "; restructure: " + frame_list_text(restructure);
  if (!stale.empty()) text += "; stale: " + frame_list_text(stale);
  if (!ahead.empty() || !adopt.empty())
    text += "; built ahead: " + frame_list_text(ahead) + "; adopted: " + frame_list_text(adopt);
  if (!update_ahead.empty() || !adopt_update.empty())
    text += "; updated ahead: " + frame_list_text(update_ahead) + "; adopted: " + frame_list_text(adopt_update);
  return text;
}

std::vector<uint32_t> frames_that_differ(const RecordedPlan& a, const RecordedPlan& b) {
  std::vector<uint32_t> differ;
  const size_t n = std::max(a.frames.size(), b.frames.size());
  for (size_t k = 0; k < n; ++k) {
    const bool both = k < a.frames.size() && k < b.frames.size();
    if (both && a.frames[k].frame == b.frames[k].frame && a.frames[k].step == b.frames[k].step) continue;
    differ.push_back(k < a.frames.size() ? a.frames[k].frame : b.frames[k].frame);
  }
  return differ;
}

void check_plan_frames(const RecordedPlan& plan, uint32_t first, uint32_t last) {
  const size_t needed = last - first;
  if (plan.frames.empty()) fail(plan.source + ": the plan has no frames");
  if (plan.frames.front().frame != first)
    fail(plan.where(0) + ": the plan starts at frame " + std::to_string(plan.frames.front().frame) +
         ", the run at frame " + std::to_string(first) + " (--frames " + std::to_string(first) + ":" +
         std::to_string(last) + ")");
  if (plan.frames.size() < needed)
    fail(plan.source + ": the plan records " + std::to_string(plan.frames.size()) + " frames (" +
         std::to_string(first) + " to " + std::to_string(plan.frames.back().frame) + "), the run's frames " +
         std::to_string(first) + ":" + std::to_string(last) + " are " + std::to_string(needed) +
         ": run fewer frames (--frames) or record a longer plan");
}

void check_plan_steps(const RecordedPlan& plan, const ReplayTarget& target) {
  // The side's work in flight: launched, not adopted yet (a build ahead, or an update ahead).
  bool ahead = false;
  TreeStep launched = TreeStep::ahead;  // which, while one runs
  for (size_t k = 0; k < plan.frames.size(); ++k) {
    const PlanStep& s = plan.frames[k].step;
    const auto refuse = [&](const std::string& why) { fail(plan.where(k) + ": " + why); };
    const bool built = s.trees == TreeStep::build;
    const bool launches = s.trees == TreeStep::ahead || s.trees == TreeStep::update_ahead;
    const bool adopts = s.trees == TreeStep::adopt || s.trees == TreeStep::adopt_update;
    if ((launches || adopts) && !target.builds_ahead)
      refuse(std::string(tree_step_name(s.trees)) +
             ", but this run does not build ahead (--rebuild-ahead, which needs a front pipeline with the histogram "
             "sort, no rigid objects and --refit-every 1)");
    if (launches && ahead)
      refuse(std::string(tree_step_name(s.trees)) + ", but the last " + side_work_name(launched) +
             " was not adopted yet");
    if (s.trees == TreeStep::adopt && !(ahead && launched == TreeStep::ahead)) refuse("adopt, but no build ahead runs");
    if (s.trees == TreeStep::adopt_update && !(ahead && launched == TreeStep::update_ahead))
      refuse("adopt-update, but no update ahead runs");
    if (built && ahead) refuse("build, but " + a_side_work(launched) + " was not adopted yet");
    const bool in_flight = ahead || launches;
    if (in_flight) {
      const std::string running = a_side_work(ahead ? launched : s.trees);
      for (Query q : kQueries)
        if (s.op(q) && *s.op(q) != FrontOp::preserve)
          refuse("while " + running + " runs every front is preserved; " + query_name(q) + " " +
                 front_op_name(*s.op(q)) + "s");
      if (s.inspect || s.probe)
        refuse("while " + running + " runs nothing is inspected or probed");
    }
    if (launches) {
      ahead = true;
      launched = s.trees;
    }
    if (adopts) ahead = false;
    if (k == 0 && !built)
      refuse(std::string("the first frame must build the trees (it has ") + tree_step_name(s.trees) + ")");
    for (Query q : kQueries) {
      const std::optional<FrontOp> op = s.op(q);
      if (built && op && *op != FrontOp::generate)
        refuse(std::string("a build renumbers the tree's leaves, so every front is generated; ") + query_name(q) + " " +
               front_op_name(*op) + "s");
      if (op == FrontOp::restructure && q != Query::self)
        refuse(std::string("only the self fronts restructure, not ") + query_name(q));
    }
    const bool after_inspection = k > 0 && plan.frames[k - 1].step.inspect;
    if (!target.restructures && (s.runs(FrontOp::restructure) || s.decision != Formula2::none || s.inspect))
      refuse("restructures, Formula 2 decisions and inspections are pipeline c's (the strategy restructure); this "
             "pipeline has none");
    if (s.decision != Formula2::none && !after_inspection)
      refuse(std::string("decision=") + formula2_name(s.decision) + " needs an inspection on the frame before");
    if (s.decision == Formula2::rebuild && !built && s.trees != TreeStep::ahead)
      refuse("decision=rebuild must build the trees (build, or ahead)");
    if (s.op(Query::self) == FrontOp::restructure) {
      if (built) refuse("a restructure refits the tree, it does not build it");
      if (s.decision != Formula2::restructure) refuse("a restructure is Formula 2's: it needs decision=restructure");
      if (s.op(Query::inter) && *s.op(Query::inter) != FrontOp::generate)
        refuse("a restructure renumbers T_D's leaves, so the cross fronts are generated (inter=generate)");
    }
    const std::optional<FrontOp> self = s.op(Query::self);
    if (s.inspect && !(self == FrontOp::update || (self == FrontOp::generate && !built)))
      refuse("an inspection follows an update or a generate of the self fronts on a refitted tree");
    if (s.probe && (built || !s.runs(FrontOp::preserve)))
      refuse("a probe counts what an update of preserved fronts would make: it needs a preserve on a refitted tree");
    // Stale boxes only where the run's own --refit-every keeps them, so a replay is as
    // conservative as the run's configuration says.
    const bool stale_here = !built && !target.rebuild_every_frame && !refit_due(k, target.refit_every);
    if (s.trees == TreeStep::stale && !stale_here)
      refuse("stale, but this run refits here (--refit-every " + std::to_string(target.refit_every) + ")");
    if (s.trees == TreeStep::refit && stale_here)
      refuse("refit, but this run keeps stale boxes here (--refit-every " + std::to_string(target.refit_every) + ")");
  }
}

void check_plan_queries(const RecordedPlan& plan, const QuerySet& running) {
  for (size_t k = 0; k < plan.frames.size(); ++k)
    for (Query q : kQueries) {
      const bool given = plan.frames[k].step.op(q).has_value();
      if (given == running[size_t(q)]) continue;
      fail(plan.where(k) + ": query " + query_name(q) +
           (given ? " does not run in this scene" : " runs in this scene, and the plan gives it no operation") +
           " (the plan was recorded on another scene's queries)");
    }
}

}  // namespace cdb
