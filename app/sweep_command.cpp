#include "sweep_command.h"
#include "path_checks.h"
#include "number_checks.h"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "cdbench/core/error.h"
#include "exit_codes.h"
#include "frame_range.h"
#include "options.h"
#include "cdbench/pipeline/pipeline.h"
#include "run_command.h"
#include "sweep_plan.h"
#include "sweep_runner.h"
#include "registry/pipeline_kinds.h"
#include "scenes/load/scene.h"
#include "scenes/load/scene_label.h"

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

// The error `cdbench run` would stop each cell with once it opens the cell's scene: a scene
// that does not open (unknown, missing data, a bad descriptor) or --frames past its end;
// "" where none. Each scene with its --set values is opened once for all its cells; a
// procedural scene's frames are not made for it, a directory of frames is read through
// (as run checks it before its first frame).
std::vector<std::string> cell_scene_errors(const SweepPlan& plan, const std::string& scenes_dir_given) {
  struct Opened {
    std::string error;
    uint32_t frames = 0;
  };
  std::map<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>, Opened> opened;
  std::vector<std::string> errors;
  for (const SweepCell& c : plan.cells) {
    const std::string at = "/scenes/" + std::to_string(c.scene_index) + ": ";
    auto [it, added] = opened.try_emplace({c.scene, c.set});
    if (added) {
      std::vector<std::string> sets;
      for (const auto& [key, value] : c.set) sets.push_back(key + "=" + value);
      try {
        it->second.frames = open_scene(c.scene, scenes_dir(scenes_dir_given), parse_set_overrides(sets))
                                .source->num_frames();
      } catch (const Error& e) {
        it->second.error = e.what();
      }
    }
    std::string error = it->second.error;
    if (error.empty()) {
      try {
        parse_frame_range(c.frames, it->second.frames);
      } catch (const Error& e) {
        error = e.what();
      }
    }
    errors.push_back(error.empty() ? "" : at + error);
  }
  return errors;
}

// --out DIR, before anything is made: a directory that could not be created, or one where
// nothing can be written, is refused. Made and removed again at the deepest directory that
// exists: the only test that also holds for root and for read-only mounts, and a dry run
// leaves nothing behind.
void check_sweep_out(const std::string& out_dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path existing = fs::absolute(out_dir, ec).lexically_normal();
  while (!existing.empty() && !fs::exists(existing, ec) && existing != existing.parent_path())
    existing = existing.parent_path();
  if (!fs::is_directory(existing, ec))
    fail_usage("--out " + out_dir + ": cannot create the directory: " + existing.string() + " is not a directory");
  const fs::path probe = existing / (".cdbench-write-test-" + std::to_string(getpid()));
  if (mkdir(probe.c_str(), 0700) != 0) {
    const int error = errno;
    // /proc and /sys refuse new entries with ENOENT, which reads as a missing directory.
    const std::string why = error == ENOENT ? "the file system does not take new files here" : std::strerror(error);
    fail_usage("--out " + out_dir + ": cannot write in " + existing.string() + ": " + why);
  }
  rmdir(probe.c_str());
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
  if (const std::string merged = merged_cells_line(plan); !merged.empty()) std::printf("%s\n", merged.c_str());
  std::error_code ec;
  if (std::filesystem::exists(w.out_dir, ec) && !std::filesystem::is_directory(w.out_dir, ec))
    fail_usage("--out " + w.out_dir + ": not a directory; name a directory for the cells' results, logs and status");
  check_sweep_out(w.out_dir);
  SweepRunOptions options;
  options.out_dir = w.out_dir;
  options.scenes_dir = w.scenes_dir.empty() ? "" : std::filesystem::absolute(w.scenes_dir).string();
  std::vector<std::string> errors;
  size_t invalid = 0;
  for (const SweepCell& c : plan.cells) {
    errors.push_back(cell_option_error(cell_run_args(plan, c, options.out_dir, options.scenes_dir)));
    invalid += !errors.back().empty();
  }
  // A cell on cuda where there is no GPU fails here but runs where the sweep is meant to
  // (the committed sweeps are GPU sweeps): said, not refused. A Slurm script runs elsewhere.
  const size_t cuda_cells = size_t(std::count_if(plan.cells.begin(), plan.cells.end(),
                                                 [](const SweepCell& c) { return c.device == "cuda"; }));
  if (cuda_cells && w.slurm.script.empty()) {
    const CudaDeviceInfo gpu = cuda_device_info();
    if (!gpu.available)
      std::printf("warning: %s: %zu of %zu cells run on cuda and this machine has no CUDA device (%s): they fail "
                  "here; run the sweep where there is a GPU\n",
                  w.file.c_str(), cuda_cells, plan.cells.size(), gpu.reason.c_str());
  }
  if (w.dry_run) {
    // Also what run finds once it opens the scene; the sweep itself runs such cells and
    // records their failure, so the other cells still run.
    const std::vector<std::string> scene_errors = cell_scene_errors(plan, options.scenes_dir);
    for (size_t i = 0; i < plan.cells.size(); ++i)
      if (errors[i].empty() && !scene_errors[i].empty()) {
        errors[i] = scene_errors[i];
        ++invalid;
      }
    list_cells(plan, options, errors);
    for (size_t i = 0; i < plan.cells.size(); ++i)
      if (!errors[i].empty())
        std::fprintf(stderr, "cdbench: error: %s: cell %s: %s\n", w.file.c_str(), plan.cells[i].name.c_str(),
                     errors[i].c_str());
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
