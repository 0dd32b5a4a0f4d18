#include "option_table.h"

namespace cdb {

// One row per option of `run`: a new option gets its row here (the option_table test says
// which is missing), its binding and help text in options.cpp or run_command.cpp.
std::span<const OptionRow> option_table() {
  using enum OptionScope;
  using enum ComparedAs;
  using enum InSweep;
  static constexpr OptionRow rows[] = {
      // Identity: the pair set (what counts as a pair, the boxes) and how time is measured
      // (--check's work between frames, the cache, events between kernels, the warm-up).
      // compare lists differences in this order.
      {"skip-adjacent", every, identity},
      {"box-precision", every, identity},
      {"box-margin", every, identity},
      {"boxes", every, identity},
      {"refit-every", hierarchy, identity},
      {"check", every, identity},
      {"contact-distance", every, identity},
      {"contact-substeps", every, identity},
      {"cold", every, identity},
      {"phase-timing", every, identity},
      {"warmup-ms", every, identity},

      // Settings: the pipeline, its tree, fronts and restructuring, the launches, the plans,
      // the span over which the host's load is sampled (outside the measured frames).
      {"rebuild-every", hierarchy, setting},
      {"morton-bits", hierarchy, setting},
      {"refit-levels", hierarchy, setting},
      {"refit-top-leaves", hierarchy, setting},
      {"build-pieces", hierarchy, setting},
      {"split-objects", hierarchy, setting},
      {"front-cycle", fronts, setting},
      {"cuda-graph", fronts, setting},
      {"preserve-warp", fronts, setting},
      {"update-warp", fronts, setting},
      {"preserve-bound", fronts, setting},
      {"preserve-two-nodes", fronts, setting},
      {"order-updates", fronts, setting},
      {"update-in-place", fronts, setting},
      {"compact-share", fronts, setting},
      {"rebuild-degraded", fronts, setting},
      {"rebuild-ahead", fronts, setting},
      {"maintain-ahead", fronts, setting},
      {"ahead-generate", fronts, setting},
      {"rebuild-growth", fronts, setting},
      {"regenerate", fronts, setting},
      {"update-probe", fronts, setting},
      {"update-ahead", fronts, setting},
      {"restructure-quality", restructure, setting},
      {"restructure-min-leaves", restructure, setting},
      {"restructure-max-fraction", restructure, setting},
      {"threshold-refit", restructure, setting},
      {"threshold-build", restructure, setting},
      {"restructure-price", restructure, setting},
      {"dependent-launch", every, setting},
      {"repeat-plan", every, setting},
      {"load-window-ms", every, setting},

      // Not compared. The scene, pipeline, device, frames and warm-up are in the identity as
      // the file resolved them (scene_label, backend, frame_first/frame_last, warmup).
      {"scene", every, not_compared, per_cell},
      {"set", every, not_compared, per_cell},
      {"pipeline", every, not_compared, per_cell},
      {"device", every, not_compared, per_cell},
      {"frames", every, not_compared, per_cell},
      {"warmup", every, not_compared, per_cell},
      {"scenes-dir", every, not_compared},
      {"repeat", every, not_compared},
      {"max-noise", every, not_compared},
      {"out", every, not_compared, per_cell},
      {"overwrite", every, not_compared},
      {"save-pairs", every, not_compared, per_cell},
      {"label", every, not_compared},
      {"json", every, not_compared},
      {"quiet", every, not_compared, per_cell},
  };
  return rows;
}

const OptionRow* find_option_row(const std::string& name) {
  for (const OptionRow& row : option_table())
    if (name == row.name) return &row;
  return nullptr;
}

OptionScope option_scope(const std::string& flag) {
  const OptionRow* row = flag.rfind("--", 0) == 0 ? find_option_row(flag.substr(2)) : nullptr;
  return row ? row->scope : OptionScope::every;
}

std::vector<std::string> identity_options() {
  std::vector<std::string> names;
  for (const OptionRow& row : option_table())
    if (row.compared_as == ComparedAs::identity) names.push_back(row.name);
  return names;
}

bool ignored_by_compare(const std::string& name) {
  const OptionRow* row = find_option_row(name);
  return row && row->compared_as == ComparedAs::not_compared;
}

bool sweep_sets(const std::string& name) {
  const OptionRow* row = find_option_row(name);
  return row && row->in_sweep == InSweep::per_cell;
}

}  // namespace cdb
