#pragma once
// Runs a sweep's cells, each as its own `cdbench run` process, so a crash, an out-of-memory
// kill or an error in one cell is recorded and the others go on; or lists them. (A Slurm job
// array of them: slurm_script.h.)
#include <filesystem>
#include <string>
#include <vector>

#include "cell_status.h"
#include "sweep_plan.h"

namespace cdb {

struct SweepRunOptions {
  std::filesystem::path out_dir;
  std::string scenes_dir;      // passed on to every cell when not empty
  unsigned slots = 1;          // cells run at a time
  bool one_gpu_each = false;   // give the cell in slot k only GPU k (CUDA_VISIBLE_DEVICES)
};

// True when the cell's results file exists and says `complete`.
bool cell_complete(const std::filesystem::path& out_dir, const SweepCell& cell);

// A status naming the cell (cell, scene, pipeline, device, command line, log), its state
// still to be set.
CellStatus status_of(const SweepPlan& plan, const SweepCell& cell, const SweepRunOptions& options);

// --dry-run: every cell with its state and command line. `option_errors`: per cell, the
// error its run would stop with before loading the scene ("" for none), listed as INVALID.
void list_cells(const SweepPlan& plan, const SweepRunOptions& options, const std::vector<std::string>& option_errors);

// Runs the cells not yet complete. Returns 0 when every cell is complete, 1 when some
// failed, 128 + signal when SIGINT/SIGTERM stopped the sweep (running cells are passed the
// signal and end as incomplete files).
int run_sweep(const SweepPlan& plan, const SweepRunOptions& options);

}  // namespace cdb
