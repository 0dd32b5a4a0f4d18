#include "sweep_command.h"
#include "path_checks.h"
#include "number_checks.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <vector>

#include "cdbench/core/error.h"
#include "exit_codes.h"
#include "options.h"
#include "cdbench/pipeline/pipeline.h"
#include "run_command.h"
#include "sweep_plan.h"
#include "sweep_runner.h"
#include "registry/pipeline_kinds.h"

namespace cdb {
namespace {

// The error `cdbench run` would stop the cell with before loading its scene: its command
// line parsed by the run command's own definition, then run's own checks; "" when none.
std::string cell_option_error(const std::vector<std::string>& args) {
  CLI::App app;
  CommonOptions o;
  RunOptions r;
  add_run_command(app, o, r);
  // CLI11 takes the arguments last first.
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  try {
    app.parse(reversed);
    check_run_options(o, r, o.device);
  } catch (const CLI::ParseError& e) {
    return e.what();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

CLI::App* add_sweep_command(CLI::App& app, SweepOptions& w) {
  auto* sweep = app.add_subcommand("sweep", "run the cells of a sweep file, one process each (docs/sweeps.md)");
  sweep->add_option("file", w.file, "sweep file (.json)")->required();
  sweep->add_option("--out", w.out_dir, "directory for the cells' results files, logs and status")
      ->required()
      ->check(non_empty_path());
  sweep->add_option("--gpus", w.gpus,
                    "cells at a time, one GPU each (CUDA_VISIBLE_DEVICES); default: the GPUs visible, 1 without")
      ->check(whole_in(1, 1024));
  add_slurm_options(*sweep, w.slurm);
  sweep->add_flag("--dry-run", w.dry_run, "list the cells, their state and command lines; run nothing");
  sweep->add_option("--scenes-dir", w.scenes_dir, "where named scenes live, passed on to every cell");
  return sweep;
}

int sweep_command(const SweepOptions& w, const CLI::App& run) {
  std::vector<RunOptionInfo> run_options;
  for (const CLI::Option* opt : run.get_options())
    if (!opt->get_lnames().empty()) run_options.push_back({opt->get_lnames()[0], opt->get_expected_max() == 0});
  // The sweep file is the sweep's command line: its errors are usage errors.
  const SweepPlan plan = [&] {
    try {
      return load_sweep(w.file, run_options, pipeline_names());
    } catch (const Error& e) {
      fail_usage(e.what());
    }
  }();
  std::error_code ec;
  if (std::filesystem::exists(w.out_dir, ec) && !std::filesystem::is_directory(w.out_dir, ec))
    fail_usage("--out " + w.out_dir + ": not a directory; name a directory for the cells' results, logs and status");
  SweepRunOptions options;
  options.out_dir = w.out_dir;
  options.scenes_dir = w.scenes_dir.empty() ? "" : std::filesystem::absolute(w.scenes_dir).string();
  std::vector<std::string> errors;
  size_t invalid = 0;
  for (const SweepCell& c : plan.cells) {
    errors.push_back(cell_option_error(cell_run_args(plan, c, options.out_dir, options.scenes_dir)));
    invalid += !errors.back().empty();
  }
  if (w.dry_run) {
    list_cells(plan, options, errors);
    return invalid ? kExitUsage : kExitOk;
  }
  if (invalid) {
    for (size_t i = 0; i < plan.cells.size(); ++i)
      if (!errors[i].empty())
        std::fprintf(stderr, "cdbench: error: %s: cell %s: %s\n", w.file.c_str(), plan.cells[i].name.c_str(),
                     errors[i].c_str());
    std::fprintf(stderr, "cdbench: %zu of %zu cells have options run refuses; nothing was run\n", invalid,
                 plan.cells.size());
    return kExitUsage;
  }
  if (!w.slurm.script.empty()) return slurm_script_command(plan, options, w.slurm);
  const int gpus = w.gpus > 0 ? w.gpus : cuda_device_info().device_count;
  options.slots = unsigned(std::max(gpus, 1));
  options.one_gpu_each = gpus > 0;
  return run_sweep(plan, options);
}

}  // namespace cdb
