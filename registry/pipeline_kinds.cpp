#include "registry/pipeline_kinds.h"

#include "cdbench/core/error.h"

namespace cdb {

const std::vector<PipelineKind>& pipeline_kinds() {
  using M = BaselineMethod;
  // static = b and restructure = c: the paper's strategy names (§5.2, Fig. 5) beside its pipelines.
  static const std::vector<PipelineKind> kinds = {
      {"bvh", "", "ordered LBVH built on the first frame (and every --rebuild-every K), refitted, queried", M::bvh},
      {"unordered", "unordered", "fronts preserved and updated, never sorted", FrontStrategy{.ordered = false}},
      {"static", "static", "b: fronts sorted, and balanced before every update", FrontStrategy{.balance = true}},
      {"periodic", "periodic", "static, but every second maintenance generates the fronts instead of updating them",
       FrontStrategy{.balance = true, .periodic = true}},
      {"restructure", "restructure", "c: b plus quality inspection and restructuring (Formulas 1 and 2)",
       FrontStrategy{.balance = true, .restructure = true}},
      {"reference", "reference", "the hierarchy rebuilt and the fronts generated every frame",
       FrontStrategy{.rebuild_every_frame = true}},
      {"a", "pipeline a", "fronts sorted (histogram), preserved and updated", FrontStrategy{}},
      {"b", "pipeline b", "a plus balancing before every update", FrontStrategy{.balance = true}},
      {"c", "pipeline c", "b plus quality inspection and restructuring (Formulas 1 and 2)",
       FrontStrategy{.balance = true, .restructure = true}},
      {"radix-order", "radix sort (Fig. 6)", "static with fronts and hierarchy ordered by a radix sort",
       FrontStrategy{.balance = true, .radix_sort = true}},
      {"sweep", "", "sort-and-sweep along the axis of largest centroid variance, every frame", M::sweep},
      {"hash", "", "uniform-grid spatial hashing (kDet style), every frame", M::hash},
      {"grid", "", "uniform grid with size levels (OTG style), every frame", M::grid},
      {"brute", "", "every pair tested, O(N^2): the oracle", M::brute},
      // How a method of one's own comes in (docs/extending.md); last, so no one takes it
      // for one of the compared pipelines.
      {"example-sap", "",
       "EXAMPLE for docs/extending.md, not a tuned baseline: textbook sort-and-sweep along x, every frame",
       M::example_sap}};
  return kinds;
}

const PipelineKind* find_pipeline_kind(const std::string& name) {
  for (const PipelineKind& k : pipeline_kinds())
    if (name == k.name) return &k;
  return nullptr;
}

const std::vector<std::string>& pipeline_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const PipelineKind& k : pipeline_kinds()) n.push_back(k.name);
    return n;
  }();
  return names;
}

bool config_conservative(const PipelineConfig& config) {
  // The baselines but bvh (which start every frame from the positions) and the per-frame
  // rebuild never keep stale boxes.
  const PipelineKind* kind = find_pipeline_kind(config.name);
  if (!kind) return config.tree.refit_every <= 1;
  const auto* method = std::get_if<BaselineMethod>(&kind->builds);
  const bool fresh = method ? *method != BaselineMethod::bvh : std::get<FrontStrategy>(kind->builds).rebuild_every_frame;
  return fresh || config.tree.refit_every <= 1;
}

std::unique_ptr<Pipeline> make_pipeline(const PipelineConfig& config) {
  if (!find_pipeline_kind(config.name)) {
    std::string list;
    for (const auto& n : pipeline_names()) list += (list.empty() ? "" : ", ") + n;
    fail("unknown pipeline '" + config.name + "' (known: " + list + ")");
  }
  if (config.device != "cpu" && config.device != "cuda")
    fail("unknown device '" + config.device + "' (known: cuda, cpu)");
  std::unique_ptr<Pipeline> p = config.device == "cpu" ? make_host_pipeline(config) : make_cuda_pipeline(config);
  if (!p) fail("pipeline '" + config.name + "' is not available on " + config.device);
  return p;
}

}  // namespace cdb
