#include "harness/plans/plan_source.h"

#include <algorithm>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <vector>

#include "cdbench/core/error.h"
#include "scenes/load/input_files.h"
#include "harness/results/results_reader.h"

namespace cdb {
namespace {

namespace fs = std::filesystem;

bool is_hdf5(const fs::path& path) {
  static constexpr char kSignature[8] = {'\x89', 'H', 'D', 'F', '\r', '\n', '\x1a', '\n'};
  char head[8] = {};
  std::ifstream in(path, std::ios::binary);
  return in.read(head, sizeof head) && std::equal(head, head + 8, kSignature);
}

RecordedPlan results_plan(const std::string& file, const std::vector<std::string>& selector,
                          const std::string& pipeline) {
  const ResultsPlans plans = read_results_plans(file);
  const std::string wanted = selector.empty() ? pipeline : selector[0];
  if (!wanted.empty() && plans.pipeline != wanted)
    fail(file + " holds pipeline " + plans.pipeline + "'s plans, not " + wanted + "'s" +
         (selector.empty() ? ": name the pipeline to replay its plan on " + pipeline + " (" + file + ":" +
                                 plans.pipeline + ")"
                           : ""));
  if (plans.passes.empty())
    fail(file + ": no plans recorded (pipeline " + plans.pipeline +
         " has no front plan, or the file predates them: results schema 4)");
  uint32_t pass = 0;
  if (selector.size() == 2) {
    const std::string& p = selector[1];
    const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), pass);
    if (ec != std::errc() || end != p.data() + p.size())
      fail(file + ":" + selector[0] + ":" + p + ": the pass is a whole number");
  }
  if (pass >= plans.passes.size())
    fail(file + ": pipeline " + plans.pipeline + " ran passes 0 to " + std::to_string(plans.passes.size() - 1) +
         "; there is no pass " + std::to_string(pass));
  return plans.passes[pass];
}

}  // namespace

RecordedPlan load_plan(const std::string& spec, const std::string& pipeline) {
  // FILE, FILE:PIPELINE or FILE:PIPELINE:PASS: the longest prefix that names a file.
  std::string file = spec;
  std::vector<std::string> selector;
  std::error_code ec;
  while (!fs::exists(file, ec) && selector.size() < 2) {
    const size_t colon = file.rfind(':');
    if (colon == std::string::npos) break;
    selector.insert(selector.begin(), file.substr(colon + 1));
    file.resize(colon);
  }
  if (!fs::is_regular_file(file, ec))
    fail(spec + ": no such file (a plan is a plan file, or a results file FILE.h5[:PIPELINE[:PASS]])");
  if (is_hdf5(file)) return results_plan(file, selector, pipeline);
  if (!selector.empty())
    fail(spec + ": " + file + " is a plan file, not a results file: only a results file takes :PIPELINE[:PASS]");
  return parse_plan(read_file(file, " the plan file"), file);
}

}  // namespace cdb
