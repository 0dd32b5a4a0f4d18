#pragma once
// `cdbench sweep --slurm FILE`: the sweep's cells that are not complete as a Slurm job array,
// one task per cell, and the sweep options that set its #SBATCH lines.
#include <cstddef>
#include <filesystem>
#include <string>

#include "sweep_plan.h"
#include "sweep_runner.h"

namespace CLI {
class App;
}

namespace cdb {

// Defaults are what a cell of the paper's sweeps needs on a GPU node; docs/sweeps.md lists
// them. sbatch options on its command line still override the script's.
struct SlurmOptions {
  std::string script;            // --slurm FILE; empty: run the cells here instead
  std::string time = "1:00:00";  // per array task, i.e. per cell
  unsigned cpus_per_task = 4;    // also the cell's OpenMP threads
  std::string partition;         // empty: the cluster's default partition
  std::string account;           // empty: the user's default account
  std::string gres = "gpu:1";    // for arrays with a CUDA cell; "none" asks for no GPU
  unsigned throttle = 0;         // at most this many tasks at once (--array=...%N); 0: no limit
};

// Adds --slurm and the options above (each needing --slurm) to the sweep subcommand.
void add_slurm_options(CLI::App& sweep, SlurmOptions& options);

struct SlurmScript {
  size_t tasks = 0;        // cells in the array
  size_t in_progress = 0;  // of those, cells an earlier script or sweep marked pending or running
};

// Writes the script, creates every directory sbatch opens before the script runs (the
// --output and --chdir directories), and marks each cell in the array pending in its
// <cell>.status.json (task i of FILE), so `report DIR` shows it before it starts.
SlurmScript write_slurm_script(const SweepPlan& plan, const SweepRunOptions& run, const SlurmOptions& slurm);

// `sweep --slurm FILE`: writes the script and says what is in it and how to submit it.
int slurm_script_command(const SweepPlan& plan, const SweepRunOptions& run, const SlurmOptions& slurm);

}  // namespace cdb
