// app/option_table.cpp against the options `run` binds: a row for every option the results
// file records, no row for an option that is not there; and the one phrasing of an option
// that does not apply to a pipeline.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "option_scope.h"
#include "option_table.h"
#include "run_command.h"

namespace cdb {
namespace {

// The long names of the options `run` binds, as params_json's options records them (CLI11's
// --help left out, as cli_params.cpp leaves it out).
std::set<std::string> run_option_names() {
  CLI::App app;
  CommonOptions common;
  RunOptions run;
  std::set<std::string> names;
  for (const CLI::Option* opt : add_run_command(app, common, run)->get_options())
    if (!opt->get_lnames().empty() && opt->get_lnames()[0] != "help") names.insert(opt->get_lnames()[0]);
  return names;
}

TEST(OptionTable, EveryRunOptionHasARow) {
  const std::set<std::string> bound = run_option_names();
  ASSERT_GT(bound.size(), 40u);  // the walk saw run's options, not an empty command
  for (const std::string& name : bound)
    EXPECT_NE(find_option_row(name), nullptr)
        << "--" << name << " is bound on run but has no row in app/option_table.cpp (its scope, what compare "
        << "makes of it, whether a sweep sets it)";
}

TEST(OptionTable, EveryRowNamesARunOption) {
  const std::set<std::string> bound = run_option_names();
  std::set<std::string> rows;
  for (const OptionRow& row : option_table()) {
    EXPECT_TRUE(bound.count(row.name)) << "app/option_table.cpp has a row for --" << row.name
                                       << ", which run does not bind";
    EXPECT_TRUE(rows.insert(row.name).second) << "app/option_table.cpp has two rows for --" << row.name;
  }
}

TEST(OptionScopeText, OneFlagSeveralPipelines) {
  EXPECT_EQ(not_applying_text({"--front-cycle"}, {"bvh", "grid"}),
            "--front-cycle does not apply to bvh, grid (front pipelines only)");
}

TEST(OptionScopeText, SeveralFlagsTheirScopesOnce) {
  EXPECT_EQ(not_applying_text({"--front-cycle", "--cuda-graph", "--restructure-quality"}, {"grid"}),
            "--front-cycle, --cuda-graph, --restructure-quality do not apply to grid (front pipelines only; "
            "restructuring pipelines only: c)");
}

TEST(OptionScopeText, RunWarnsPerPipeline) {
  EXPECT_EQ(ignored_option_warnings({"--scene", "--rebuild-every", "--front-cycle"}, {"bvh", "grid", "c"}),
            (std::vector<std::string>{
                "--front-cycle does not apply to bvh (front pipelines only): ignored there",
                "--rebuild-every, --front-cycle do not apply to grid (BVH pipelines only: the front pipelines and "
                "bvh; front pipelines only): ignored there"}));
}

}  // namespace
}  // namespace cdb
