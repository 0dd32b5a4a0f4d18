#pragma once
// `cdbench run`: pipelines on a scene, timed frame by frame, checked against the oracle on
// request, recorded in a results file.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>

#include "cdbench/narrow/contacts.h"
#include "options.h"
#include "run_loop.h"

namespace cdb {

struct RunOptions {
  std::string pipeline = "c";  // the paper's scheme
  bool quiet = false;
  std::string out;
  bool overwrite = false;  // --overwrite: --out may replace an existing file (once the run completes)
  std::string label;  // --label: stored in the results file, shown by report and compare
  bool json = false;  // --json: a JSON summary on stdout, the human output on stderr
  std::string check = "off";
  double contact_distance = 0.0;                     // as given; used as a float
  uint32_t contact_substeps = ContactCheck{}.substeps;
  // --warmup, --save-pairs, --repeat, --max-noise and --cold in loop.measuring, as the
  // measuring loop takes them; the console's options beside them.
  RunLoopOptions loop;
};

CLI::App* add_run_command(CLI::App& app, CommonOptions& o, RunOptions& r);

// What `run` checks of its options before it loads the scene, throwing UsageError with
// the message the run would print: the pipeline list and each pipeline's configuration
// (made on `device` when it is "cpu"; a CUDA pipeline needs the device to be made),
// --check and the contact options, --frames' form, {pipeline} in --out. A sweep checks
// its cells with it (sweep --dry-run included), so a cell's options fail before it runs.
void check_run_options(const CommonOptions& o, const RunOptions& r, const std::string& device);

// `cli_options`: the command's options as the results file records them (cli_params.h).
int run_command(const CommonOptions& o, const RunOptions& r, const nlohmann::json& cli_options);

}  // namespace cdb
