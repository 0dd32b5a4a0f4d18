#include "harness/results/config_json.h"

#include "registry/pipeline_kinds.h"

namespace cdb {

nlohmann::json to_json(const PipelineConfig& c) {
  return {
      {"name", c.name},
      {"device", c.device},
      {"morton_bits", c.tree.morton_bits == MortonBits::b30 ? 30 : 63},
      {"rebuild_every", c.tree.rebuild_every},
      {"pairs_per_triangle", c.capacity.pairs_per_triangle},
      {"front_per_triangle", c.capacity.front_per_triangle},
      {"front_cycle", c.fronts.cycle == 0 ? nlohmann::json("auto") : nlohmann::json(c.fronts.cycle)},
      {"skip_adjacent", c.skip_adjacent},
      {"restructure_quality", c.restructure.quality},
      {"restructure_min_leaves", c.restructure.min_leaves},
      {"restructure_max_fraction", c.restructure.max_fraction},
      {"threshold_refit", c.restructure.threshold_refit},
      {"threshold_build", c.restructure.threshold_build},
      {"restructure_price", c.restructure.priced},
      {"box_margin", c.boxes.margin},
      {"boxes", c.boxes.swept ? "swept" : "discrete"},
      {"box_precision", box_precision_name(c.boxes.precision)},
      {"refit_every", c.tree.refit_every},
      {"cuda_graph", c.launch.cuda_graph},
      {"dependent_launch", c.launch.dependent_launch},
      {"phase_timing", c.launch.phase_timing},
      {"preserve_warp", auto_switch_name(c.fronts.preserve_warp)},
      {"update_warp", auto_switch_name(c.fronts.update_warp)},
      {"preserve_bound", auto_switch_name(c.fronts.preserve_bound)},
      {"preserve_two_nodes", auto_switch_name(c.fronts.preserve_two_nodes)},
      {"order_updates", c.fronts.order_updates},
      {"update_in_place", c.fronts.update_in_place},
      {"compact_share", c.fronts.compact_share},
      {"regenerate", c.fronts.regenerate},
      {"update_probe", c.fronts.update_probe},
      {"update_ahead", auto_switch_name(c.fronts.update_ahead)},
      {"refit_top_leaves", c.tree.refit_top_leaves},
      {"refit_levels", auto_switch_name(c.tree.refit_levels)},
      {"build_pieces", auto_switch_name(c.tree.build_pieces)},
      {"rebuild_degraded", c.tree.rebuild_degraded},
      {"rebuild_ahead", auto_switch_name(c.tree.rebuild_ahead)},
      {"maintain_ahead", auto_switch_name(c.tree.maintain_ahead)},
      {"ahead_generate", c.tree.ahead_placed ? "place" : "scatter"},
      {"rebuild_growth", c.tree.rebuild_growth},
      {"split_objects", split_rule_name(c.tree.split)},
      {"conservative", config_conservative(c)},
  };
}

}  // namespace cdb
