// Recorded front plans alone: the plan file's text both ways, its errors naming the file,
// line and field, the compact outline report prints, and the checks a plan passes before
// a pipeline replays it.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "error_of.h"
#include "cdbench/pipeline/plan_record.h"

using namespace cdb;
using cdb::test::error_of;

namespace {

PlanStep step(TreeStep trees, FrontOp self, Formula2 decision = Formula2::none, bool inspect = false) {
  PlanStep s;
  s.trees = trees;
  s.op(Query::self) = self;
  s.decision = decision;
  s.inspect = inspect;
  return s;
}

// Frames 0.. of one self query: b(uild), p(reserve), u(pdate and inspect), g(enerate), r(estructure), s(tale),
// a(head: refit, preserve and build ahead), d (adopt what was built ahead, preserve).
RecordedPlan plan_of(const std::string& letters, const std::string& source = "plan.txt") {
  RecordedPlan plan;
  plan.source = source;
  for (size_t k = 0; k < letters.size(); ++k) {
    PlanStep s;
    switch (letters[k]) {
      case 'b': s = step(TreeStep::build, FrontOp::generate); break;
      case 'p': s = step(TreeStep::refit, FrontOp::preserve); break;
      case 'u': s = step(TreeStep::refit, FrontOp::update, Formula2::none, true); break;
      case 'g': s = step(TreeStep::refit, FrontOp::generate); break;
      case 'r': s = step(TreeStep::refit, FrontOp::restructure, Formula2::restructure); break;
      case 's': s = step(TreeStep::stale, FrontOp::preserve); break;
      case 'a': s = step(TreeStep::ahead, FrontOp::preserve); break;
      case 'd': s = step(TreeStep::adopt, FrontOp::preserve); break;
      case 'U': s = step(TreeStep::update_ahead, FrontOp::preserve); break;
      case 'V': s = step(TreeStep::adopt_update, FrontOp::preserve); break;
    }
    plan.frames.push_back({uint32_t(k), s, 0});
  }
  return plan;
}

const ReplayTarget kPipelineC{true, false, 1};
const ReplayTarget kPipelineA{false, false, 1};
const ReplayTarget kPipelineCAhead{true, false, 1, true};

}  // namespace

TEST(PlanRecord, TextRoundTrip) {
  const std::string text =
      "cdbench-plan 1\n"
      "# recorded by hand\n"
      "\n"
      "4 build self=generate inter=generate\n"
      "5 refit self=preserve inter=preserve probe   # steady\n"
      "6 refit self=update inter=update inspect\n"
      "7 refit self=restructure inter=generate decision=restructure\n"
      "8\tstale self=preserve inter=preserve\n";
  const RecordedPlan plan = parse_plan(text, "plan.txt");
  ASSERT_EQ(plan.frames.size(), 5u);
  EXPECT_EQ(plan.frames[0].frame, 4u);
  EXPECT_EQ(plan.frames[0].line, 4u);
  EXPECT_EQ(plan.frames[2].step.op(Query::inter), FrontOp::update);
  EXPECT_TRUE(plan.frames[2].step.inspect);
  EXPECT_TRUE(plan.frames[1].step.probe);
  EXPECT_FALSE(plan.frames[2].step.probe);
  EXPECT_TRUE(plan.records_probes);
  EXPECT_FALSE(parse_plan("cdbench-plan 1\n0 build self=generate\n1 refit self=update\n", "p.txt").records_probes);
  EXPECT_FALSE(plan.frames[2].step.op(Query::rigid_self).has_value());
  EXPECT_EQ(plan.frames[3].step.decision, Formula2::restructure);
  EXPECT_EQ(plan.frames[4].step.trees, TreeStep::stale);
  EXPECT_EQ(plan.where(3), "plan.txt line 7 (frame 7)");
  EXPECT_EQ(format_plan_step(plan.frames[3].step), "refit self=restructure inter=generate decision=restructure");
  const RecordedPlan again = parse_plan(format_plan(plan, {"a comment"}), "again.txt");
  ASSERT_EQ(again.frames.size(), plan.frames.size());
  for (size_t k = 0; k < plan.frames.size(); ++k) {
    EXPECT_EQ(again.frames[k].frame, plan.frames[k].frame);
    EXPECT_EQ(again.frames[k].step, plan.frames[k].step) << "frame " << k;
  }
  EXPECT_EQ(format_plan(plan).substr(0, 15), "cdbench-plan 1\n");
  EXPECT_TRUE(again.records_probes);
  EXPECT_EQ(format_plan_step(plan.frames[1].step), "refit self=preserve inter=preserve probe");
}

TEST(PlanRecord, ParseErrorsNameTheFileLineAndField) {
  const std::string h = "cdbench-plan 1\n0 build self=generate\n";
  const struct {
    std::string text, error;
  } cases[] = {
      {"", "p.txt: not a cdbench plan file: empty (expected the header 'cdbench-plan 1')"},
      {"cdbench-plan 1\n# nothing\n", "p.txt: the plan has no frames (one line per frame after the header)"},
      {"0 build self=generate\n",
       "p.txt line 1: not a cdbench plan file: expected the header 'cdbench-plan 1', got '0 build self=generate'"},
      {"cdbench-plan 2\n", "p.txt line 1: plan format version 2; this cdbench reads version 1"},
      {h + "x refit self=preserve\n", "p.txt line 3 field 1 ('x'): expected the frame's index, a whole number"},
      {h + "2 refit self=preserve\n",
       "p.txt line 3 field 1 ('2'): frame 2 after frame 0: a plan lists consecutive frames"},
      {h + "1 rebuild self=preserve\n",
       "p.txt line 3 field 2 ('rebuild'): expected the trees' step: build, refit, stale, ahead, adopt, update-ahead or adopt-update"},
      {h + "1\n", "p.txt line 3 field 2: missing the trees' step (build, refit, stale, ahead, adopt, update-ahead or adopt-update)"},
      {h + "1 refit self=updte\n",
       "p.txt line 3 field 3 ('self=updte'): unknown operation 'updte' (generate, preserve, update, restructure)"},
      {h + "1 refit self=update cross=update\n",
       "p.txt line 3 field 4 ('cross=update'): unknown query 'cross' (self, inter, rigid_self)"},
      {h + "1 refit self=update self=preserve\n", "p.txt line 3 field 4 ('self=preserve'): query self given twice"},
      {h + "1 refit self=update decision=maybe\n",
       "p.txt line 3 field 4 ('decision=maybe'): unknown decision 'maybe' (refit, restructure, rebuild)"},
      {h + "1 refit self=update inspected\n",
       "p.txt line 3 field 4 ('inspected'): expected QUERY=OP (self, inter, rigid_self), decision=D, inspect or probe"},
      {h + "1 refit self=update inspect inspect\n", "p.txt line 3 field 5 ('inspect'): inspect given twice"},
      {h + "1 refit self=preserve probe probe\n", "p.txt line 3 field 5 ('probe'): probe given twice"},
  };
  for (const auto& c : cases) EXPECT_EQ(error_of([&] { parse_plan(c.text, "p.txt"); }), c.error) << c.text;
}

TEST(PlanRecord, FrameListsAndOutline) {
  EXPECT_EQ(frame_list_text({}), "—");
  EXPECT_EQ(frame_list_text({7}), "7");
  EXPECT_EQ(frame_list_text({9, 10, 20, 21, 22, 37}), "9,10,20-22,37");
  EXPECT_EQ(frame_list_text({1, 2, 3, 4, 6, 7}), "1-4,6,7");
  EXPECT_EQ(plan_outline(plan_of("bppuppgupr")), "build: 0; update: 3,7; generate: 6; restructure: 9");
  EXPECT_EQ(plan_outline(plan_of("bpsps")), "build: 0; update: —; generate: —; restructure: —; stale: 2,4");
  EXPECT_EQ(plan_outline(plan_of("bpappdpappd")),
            "build: 0; update: —; generate: —; restructure: —; built ahead: 2,7; adopted: 5,10");
  const RecordedPlan ahead = parse_plan("cdbench-plan 1\n0 build self=generate\n1 ahead self=preserve\n2 adopt self=preserve\n", "p.txt");
  EXPECT_EQ(ahead.frames[1].step.trees, TreeStep::ahead);
  EXPECT_EQ(ahead.frames[2].step.trees, TreeStep::adopt);
  EXPECT_EQ(format_plan_step(ahead.frames[1].step), "ahead self=preserve");
  EXPECT_EQ(plan_outline(plan_of("bpUVpUpV")),
            "build: 0; update: —; generate: —; restructure: —; updated ahead: 2,5; adopted: 3,7");
  const RecordedPlan updated =
      parse_plan("cdbench-plan 1\n0 build self=generate\n1 update-ahead self=preserve\n2 adopt-update self=preserve\n",
                 "p.txt");
  EXPECT_EQ(updated.frames[1].step.trees, TreeStep::update_ahead);
  EXPECT_EQ(updated.frames[2].step.trees, TreeStep::adopt_update);
  EXPECT_EQ(format_plan_step(updated.frames[2].step), "adopt-update self=preserve");
  RecordedPlan restructure = plan_of("bur");
  restructure.frames[2].step.op(Query::inter) = FrontOp::generate;  // part of the restructure, not a maintenance
  EXPECT_EQ(plan_outline(restructure), "build: 0; update: 1; generate: —; restructure: 2");
}

TEST(PlanRecord, FramesThatDiffer) {
  EXPECT_TRUE(frames_that_differ(plan_of("bppu"), plan_of("bppu")).empty());
  EXPECT_EQ(frames_that_differ(plan_of("bppup"), plan_of("bpupp")), (std::vector<uint32_t>{2, 3}));
  EXPECT_EQ(frames_that_differ(plan_of("bpp"), plan_of("bppu")), (std::vector<uint32_t>{3}));
}

TEST(PlanRecord, TheRunsFramesMustBeRecorded) {
  RecordedPlan plan = plan_of("bppup");
  EXPECT_EQ(error_of([&] { check_plan_frames(plan, 0, 5); }), "no error");
  EXPECT_EQ(error_of([&] { check_plan_frames(plan, 0, 3); }), "no error");  // a shorter run replays a prefix
  EXPECT_EQ(error_of([&] { check_plan_frames(plan, 0, 7); }),
            "plan.txt: the plan records 5 frames (0 to 4), the run's frames 0:7 are 7: run fewer frames (--frames) "
            "or record a longer plan");
  EXPECT_EQ(error_of([&] { check_plan_frames(plan, 2, 5); }),
            "plan.txt frame 0: the plan starts at frame 0, the run at frame 2 (--frames 2:5)");
}

TEST(PlanRecord, StepsAPipelineCannotRunAreRefused) {
  const auto error = [](const RecordedPlan& p, const ReplayTarget& t) {
    return error_of([&] { check_plan_steps(p, t); });
  };
  EXPECT_EQ(error(plan_of("bppupgp"), kPipelineC), "no error");
  EXPECT_EQ(error(plan_of("bpur"), kPipelineC), "no error");
  EXPECT_EQ(error(plan_of("pbp"), kPipelineC), "plan.txt frame 0: the first frame must build the trees (it has refit)");
  EXPECT_EQ(error(plan_of("bpur"), kPipelineA),
            "plan.txt frame 2: restructures, Formula 2 decisions and inspections are pipeline c's (the strategy "
            "restructure); this pipeline has none");
  EXPECT_EQ(error(plan_of("bppr"), kPipelineC),
            "plan.txt frame 3: decision=restructure needs an inspection on the frame before");
  RecordedPlan p = plan_of("bpb");
  p.frames[2].step.op(Query::self) = FrontOp::update;
  EXPECT_EQ(error(p, kPipelineC),
            "plan.txt frame 2: a build renumbers the tree's leaves, so every front is generated; self updates");
  p = plan_of("bur");
  p.frames[2].step.decision = Formula2::refit;
  EXPECT_EQ(error(p, kPipelineC), "plan.txt frame 2: a restructure is Formula 2's: it needs decision=restructure");
  p = plan_of("bur");
  p.frames[2].step.op(Query::inter) = FrontOp::preserve;
  EXPECT_EQ(error(p, kPipelineC),
            "plan.txt frame 2: a restructure renumbers T_D's leaves, so the cross fronts are generated "
            "(inter=generate)");
  p = plan_of("bpu");
  p.frames[2].step.op(Query::inter) = FrontOp::restructure;
  EXPECT_EQ(error(p, kPipelineC), "plan.txt frame 2: only the self fronts restructure, not inter");
  p = plan_of("bpp");
  p.frames[1].step.inspect = true;
  EXPECT_EQ(error(p, kPipelineC),
            "plan.txt frame 1: an inspection follows an update or a generate of the self fronts on a refitted tree");
  for (const size_t k : {size_t(0), size_t(1)}) {
    p = plan_of("bup");
    p.frames[k].step.probe = true;
    EXPECT_EQ(error(p, kPipelineC), "plan.txt frame " + std::to_string(k) +
                                        ": a probe counts what an update of preserved fronts would make: it needs a "
                                        "preserve on a refitted tree");
  }
  p = plan_of("bup");
  p.frames[2].step.decision = Formula2::rebuild;
  EXPECT_EQ(error(p, kPipelineC), "plan.txt frame 2: decision=rebuild must build the trees (build, or ahead)");
  // Builds ahead: only on a target that builds ahead, one at a time, each adopted, every
  // front preserved meanwhile.
  EXPECT_EQ(error(plan_of("bpappdpupappd"), kPipelineCAhead), "no error");
  EXPECT_EQ(error(plan_of("bpapd"), kPipelineC),
            "plan.txt frame 2: ahead, but this run does not build ahead (--rebuild-ahead, which needs a front "
            "pipeline with the histogram sort, no rigid objects and --refit-every 1)");
  EXPECT_EQ(error(plan_of("bpapa"), kPipelineCAhead),
            "plan.txt frame 4: ahead, but the last build ahead was not adopted yet");
  EXPECT_EQ(error(plan_of("bpd"), kPipelineCAhead), "plan.txt frame 2: adopt, but no build ahead runs");
  EXPECT_EQ(error(plan_of("bpabd"), kPipelineCAhead), "plan.txt frame 3: build, but a build ahead was not adopted yet");
  EXPECT_EQ(error(plan_of("bpaud"), kPipelineCAhead),
            "plan.txt frame 3: while a build ahead runs every front is preserved; self updates");
  p = plan_of("bpapd");
  p.frames[3].step.probe = true;
  EXPECT_EQ(error(p, kPipelineCAhead), "plan.txt frame 3: while a build ahead runs nothing is inspected or probed");
  p = plan_of("buapd");
  p.frames[2].step.decision = Formula2::rebuild;
  EXPECT_EQ(error(p, kPipelineCAhead), "no error");
  // Updates ahead: the same rules, each adopted by its own kind of adoption.
  EXPECT_EQ(error(plan_of("bpUpVpapdUV"), kPipelineCAhead), "no error");
  EXPECT_EQ(error(plan_of("bpUV"), kPipelineC),
            "plan.txt frame 2: update-ahead, but this run does not build ahead (--rebuild-ahead, which needs a front "
            "pipeline with the histogram sort, no rigid objects and --refit-every 1)");
  EXPECT_EQ(error(plan_of("bpUd"), kPipelineCAhead), "plan.txt frame 3: adopt, but no build ahead runs");
  EXPECT_EQ(error(plan_of("bpaV"), kPipelineCAhead), "plan.txt frame 3: adopt-update, but no update ahead runs");
  EXPECT_EQ(error(plan_of("bpUa"), kPipelineCAhead),
            "plan.txt frame 3: ahead, but the last update ahead was not adopted yet");
  EXPECT_EQ(error(plan_of("bpUb"), kPipelineCAhead), "plan.txt frame 3: build, but an update ahead was not adopted yet");
  EXPECT_EQ(error(plan_of("bpUuV"), kPipelineCAhead),
            "plan.txt frame 3: while an update ahead runs every front is preserved; self updates");
  // Stale boxes only where the run's --refit-every keeps them.
  EXPECT_EQ(error(plan_of("bspsp"), {false, false, 2}), "no error");
  EXPECT_EQ(error(plan_of("bspsp"), kPipelineA), "plan.txt frame 1: stale, but this run refits here (--refit-every 1)");
  EXPECT_EQ(error(plan_of("bppsp"), {false, false, 2}),
            "plan.txt frame 1: refit, but this run keeps stale boxes here (--refit-every 2)");
  EXPECT_EQ(error(plan_of("bspsp"), {false, true, 2}),
            "plan.txt frame 1: stale, but this run refits here (--refit-every 2)");
}

TEST(PlanRecord, TheQueriesMustBeTheScenes) {
  const RecordedPlan p = plan_of("bpu");
  EXPECT_EQ(error_of([&] { check_plan_queries(p, {true, false, false}); }), "no error");
  EXPECT_EQ(error_of([&] { check_plan_queries(p, {true, true, false}); }),
            "plan.txt frame 0: query inter runs in this scene, and the plan gives it no operation (the plan was "
            "recorded on another scene's queries)");
  EXPECT_EQ(error_of([&] { check_plan_queries(p, {false, true, false}); }),
            "plan.txt frame 0: query self does not run in this scene (the plan was recorded on another scene's "
            "queries)");
}
