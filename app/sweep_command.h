#pragma once
// `cdbench sweep`: the cells of a sweep file, one `cdbench run` process each, here or as a
// Slurm array (docs/sweeps.md).
#include <CLI/CLI.hpp>

#include <string>

#include "slurm_script.h"

namespace cdb {

struct SweepOptions {
  std::string file, out_dir, scenes_dir;
  SlurmOptions slurm;
  int gpus = 0;  // 0: one per visible GPU, at least one cell at a time
  bool dry_run = false;
};

CLI::App* add_sweep_command(CLI::App& app, SweepOptions& w);

// `run`: the run command, whose options a sweep file may set.
int sweep_command(const SweepOptions& w, const CLI::App& run);

}  // namespace cdb
