#include "pipeline/config_json.h"

namespace cdb {

nlohmann::json to_json(const PipelineConfig& c) {
  return {
      {"name", c.name},
      {"device", c.device},
      {"morton_bits", c.morton_bits == MortonBits::b30 ? 30 : 63},
      {"rebuild_every", c.rebuild_every},
      {"pairs_per_triangle", c.pairs_per_triangle},
      {"front_per_triangle", c.front_per_triangle},
      {"front_cycle", c.front_cycle == 0 ? nlohmann::json("auto") : nlohmann::json(c.front_cycle)},
      {"skip_adjacent", c.skip_adjacent},
      {"restructure_quality", c.restructure_quality},
      {"restructure_min_leaves", c.restructure_min_leaves},
      {"restructure_max_fraction", c.restructure_max_fraction},
      {"threshold_refit", c.threshold_refit},
      {"threshold_build", c.threshold_build},
      {"box_margin", c.box_margin},
      {"boxes", c.swept_boxes ? "swept" : "discrete"},
      {"box_precision", box_precision_name(c.box_precision)},
      {"refit_every", c.refit_every},
      {"cuda_graph", c.cuda_graph},
      {"dependent_launch", c.dependent_launch},
      {"phase_timing", c.phase_timing},
      {"preserve_warp", warp_sharing_name(c.preserve_warp)},
      {"update_warp", warp_sharing_name(c.update_warp)},
      {"order_updates", c.order_updates},
      {"update_in_place", c.update_in_place},
      {"compact_share", c.compact_share},
      {"regenerate", c.regenerate},
      {"update_probe", c.update_probe},
      {"refit_top_leaves", c.refit_top_leaves},
      {"conservative", config_conservative(c)},
  };
}

}  // namespace cdb
