#pragma once
// `cdbench sweep`: a sweep file (docs/sweeps.md) expanded into cells, one `cdbench run`
// each. Pure: reads the sweep file, touches nothing else, so --dry-run, --slurm and the
// runner all see the same cells with the same names and command lines.
#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace cdb {

// A `run` option the sweep may set on an axis (from the CLI definition, so a new run
// option is sweepable without code here).
struct RunOptionInfo {
  std::string name;  // without the leading --
  bool flag = false;
};

struct SweepCell {
  std::string name;        // file-name safe, stable: scene, pipeline, device, axes, repeat
  std::string scene;       // a scene name, or an absolute path
  size_t scene_index = 0;  // its entry in the sweep file's /scenes, for messages
  std::string scene_label;
  std::vector<std::pair<std::string, std::string>> set;  // generator overrides, key order
  std::string frames;      // --frames, empty for all
  std::string pipeline, device;
  std::vector<std::pair<std::string, nlohmann::json>> options;  // axis values, key order
  unsigned repeat = 0;     // 1-based when the sweep repeats cells, else 0
};

struct SweepPlan {
  std::string file;  // as given, for messages
  unsigned warmup = 1;
  std::vector<SweepCell> cells;
  // Cells left out because they equal one kept: they differed only in an axis their
  // pipeline ignores (docs/sweeps.md). Each such axis ("--front-cycle") with the pipelines
  // that ignore it, in sweep-file order.
  size_t merged_cells = 0;
  std::map<std::string, std::vector<std::string>> ignored_axes;
};

// "sweep s.json: 2 cells merged into others: --front-cycle does not apply to bvh", or ""
// when no cell was merged.
std::string merged_cells_line(const SweepPlan& plan);

// The most cells a sweep file may make (docs/usage.md): far more than a machine runs in a
// day, few enough to list, check and write a Slurm array for at once.
inline constexpr size_t kMaxSweepCells = 10000;

// Throws cdb::Error naming the file and the JSON path of what is wrong, e.g.
// "s.json: /pipelines/2: unknown pipeline 'x'".
SweepPlan load_sweep(const std::filesystem::path& file, const std::vector<RunOptionInfo>& run_options,
                     const std::vector<std::string>& pipelines);

// The arguments after the executable: run ... --out DIR/<cell>.h5 --quiet.
std::vector<std::string> cell_run_args(const SweepPlan& plan, const SweepCell& cell,
                                       const std::filesystem::path& out_dir,
                                       const std::string& scenes_dir);

std::filesystem::path cell_results_file(const std::filesystem::path& out_dir, const SweepCell& cell);

std::string shell_quote(const std::string& word);
std::string shell_line(const std::vector<std::string>& words);

}  // namespace cdb
