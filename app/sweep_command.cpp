#include "sweep_command.h"
#include "number_checks.h"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "core/error.h"
#include "pipeline/pipeline.h"
#include "sweep_plan.h"
#include "sweep_runner.h"

namespace cdb {

CLI::App* add_sweep_command(CLI::App& app, SweepOptions& w) {
  auto* sweep = app.add_subcommand("sweep", "run the cells of a sweep file, one process each (docs/sweeps.md)");
  sweep->add_option("file", w.file, "sweep file (.json)")->required();
  sweep->add_option("--out", w.out_dir, "directory for the cells' results files, logs and status")->required();
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
  SweepRunOptions options;
  options.out_dir = w.out_dir;
  options.scenes_dir = w.scenes_dir.empty() ? "" : std::filesystem::absolute(w.scenes_dir).string();
  if (w.dry_run) {
    list_cells(plan, options);
    return 0;
  }
  if (!w.slurm.script.empty()) return slurm_script_command(plan, options, w.slurm);
  const int gpus = w.gpus > 0 ? w.gpus : cuda_device_info().device_count;
  options.slots = unsigned(std::max(gpus, 1));
  options.one_gpu_each = gpus > 0;
  return run_sweep(plan, options);
}

}  // namespace cdb
