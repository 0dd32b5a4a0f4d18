// Schema 4's front plans: each pass's steps written to /plans and read back, picked by
// FILE.h5[:PIPELINE[:PASS]] for a replay, and files without them (schema 3) still read.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "error_of.h"
#include "harness/plans/plan_source.h"
#include "harness/results/results_file.h"
#include "harness/results/results_reader.h"
#include "cdbench/pipeline/run_summary.h"

namespace cdb {
namespace {

namespace fs = std::filesystem;
using test::error_of;

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("cdb_plans_" + std::to_string(getpid()) + "_" + name);
}

PlanStep step(TreeStep trees, FrontOp self, FrontOp inter) {
  PlanStep s;
  s.trees = trees;
  s.op(Query::self) = self;
  s.op(Query::inter) = inter;
  return s;
}

// Pipeline c over frames 3..6, two passes: the second updates at frame 5, the first at 6.
fs::path write_run(const std::string& name) {
  const fs::path path = temp(name);
  RunInfo info;
  info.scene = "funnel";
  info.pipeline = "c";
  info.backend = "cpu";
  info.frame_first = 3;
  info.frame_last = 7;
  info.repeat_plan = "free";
  info.params_json = R"({"options": {"front-cycle": "auto"}})";
  ResultsFile out(path, info);
  const PlanStep build = step(TreeStep::build, FrontOp::generate, FrontOp::generate);
  const PlanStep preserve = step(TreeStep::refit, FrontOp::preserve, FrontOp::preserve);
  const PlanStep update = step(TreeStep::refit, FrontOp::update, FrontOp::update);
  const std::vector<std::vector<PlanStep>> passes = {{build, preserve, preserve, update},
                                                     {build, preserve, update, preserve}};
  for (size_t p = 0; p < passes.size(); ++p)
    for (size_t k = 0; k < passes[p].size(); ++k) out.append_plan_step(uint32_t(p), uint32_t(3 + k), passes[p][k]);
  std::vector<FrameStats> frames(4);
  for (size_t k = 0; k < frames.size(); ++k) {
    frames[k].timing.total_ms = 1.0;
    frames[k].plan = passes[1][k];
    frames[k].plan_mixed = k >= 2;
    out.append_frame(uint32_t(3 + k), frames[k], MemoryStats{});
  }
  out.finish(summarize_run(frames, 1), MemoryStats{});
  return path;
}

TEST(ResultsPlans, EachPassRoundTrips) {
  const fs::path path = write_run("two.h5");
  const ResultsPlans plans = read_results_plans(path);
  EXPECT_EQ(plans.pipeline, "c");
  ASSERT_EQ(plans.passes.size(), 2u);
  ASSERT_EQ(plans.passes[1].frames.size(), 4u);
  EXPECT_EQ(plans.passes[1].frames[0].frame, 3u);
  EXPECT_EQ(plans.passes[1].frames[2].step, step(TreeStep::refit, FrontOp::update, FrontOp::update));
  EXPECT_FALSE(plans.passes[1].frames[2].step.op(Query::rigid_self).has_value());
  EXPECT_EQ(plans.passes[0].source, path.string() + " (pipeline c, pass 0)");
  EXPECT_EQ(frames_that_differ(plans.passes[0], plans.passes[1]), (std::vector<uint32_t>{5, 6}));
  const ResultsOverview r = read_results_overview(path);
  EXPECT_TRUE(r.has_plans);
  EXPECT_EQ(r.repeat_plan, "free");
  EXPECT_EQ(r.plan_source, "");
  EXPECT_EQ(r.plan_mixed_frames, 2u);
  fs::remove(path);
}

TEST(ResultsPlans, APassIsPickedByPipelineAndPass) {
  const fs::path path = write_run("pick.h5");
  const std::string file = path.string();
  EXPECT_EQ(plan_outline(load_plan(file, "c")), "build: 3; update: 6; generate: —; restructure: —");
  EXPECT_EQ(plan_outline(load_plan(file + ":c:1", "a")), "build: 3; update: 5; generate: —; restructure: —");
  EXPECT_EQ(load_plan(file + ":c", "").source, file + " (pipeline c, pass 0)");
  EXPECT_EQ(error_of([&] { load_plan(file, "a"); }),
            file + " holds pipeline c's plans, not a's: name the pipeline to replay its plan on a (" + file + ":c)");
  EXPECT_EQ(error_of([&] { load_plan(file + ":b", "c"); }), file + " holds pipeline c's plans, not b's");
  EXPECT_EQ(error_of([&] { load_plan(file + ":c:2", "c"); }),
            file + ": pipeline c ran passes 0 to 1; there is no pass 2");
  EXPECT_EQ(error_of([&] { load_plan(file + ":c:x", "c"); }), file + ":c:x: the pass is a whole number");
  EXPECT_EQ(error_of([&] { load_plan(file + ".missing", "c"); }),
            file + ".missing: no such file (a plan is a plan file, or a results file FILE.h5[:PIPELINE[:PASS]])");
  fs::remove(path);
}

TEST(ResultsPlans, PlanFilesAreToldFromResultsFilesByTheirContent) {
  const fs::path path = temp("plan.h5");  // named like a results file, holding a plan file
  std::ofstream(path) << "cdbench-plan 1\n0 build self=generate\n1 refit self=update\n";
  EXPECT_EQ(plan_outline(load_plan(path.string(), "c")), "build: 0; update: 1; generate: —; restructure: —");
  EXPECT_EQ(error_of([&] { load_plan(path.string() + ":c", "c"); }),
            path.string() + ":c: " + path.string() +
                " is a plan file, not a results file: only a results file takes :PIPELINE[:PASS]");
  std::ofstream(path) << "cdbench-plan 1\n0 build self=generate\n1 refit self=uptade\n";
  EXPECT_EQ(error_of([&] { load_plan(path.string(), "c"); }),
            path.string() +
                " line 3 field 3 ('self=uptade'): unknown operation 'uptade' (generate, preserve, update, restructure)");
  fs::remove(path);
}

TEST(ResultsPlans, FilesWithoutPlansStillRead) {
  const fs::path path = write_run("old.h5");
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    EXPECT_GE(H5Ldelete(file, "plans", H5P_DEFAULT), 0);
    for (const char* name : {"repeat_plan", "plan_source"}) EXPECT_GE(H5Adelete(file, name), 0);
    const hid_t summary = H5Gopen2(file, "summary", H5P_DEFAULT);
    EXPECT_GE(H5Adelete(summary, "plan_mixed_frames"), 0);
    H5Gclose(summary);
    H5Fclose(file);
  }
  const ResultsOverview r = read_results_overview(path);
  EXPECT_EQ(r.status, "complete");
  EXPECT_FALSE(r.has_plans);
  EXPECT_EQ(r.repeat_plan, "");
  EXPECT_EQ(r.plan_mixed_frames, 0u);
  EXPECT_TRUE(read_results_plans(path).passes.empty());
  EXPECT_EQ(error_of([&] { load_plan(path.string(), "c"); }),
            path.string() + ": no plans recorded (pipeline c has no front plan, or the file predates them: results "
                            "schema 4)");
  fs::remove(path);
}

}  // namespace
}  // namespace cdb
