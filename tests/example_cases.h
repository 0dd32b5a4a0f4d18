#pragma once
// The example pipeline (baselines/example/, docs/extending.md) through the factory, as a
// new method's tests check it: on every frame exactly the oracle's pairs, with and without
// co-vertex filtering, on the baselines' scenes and the numerical extremes, on either
// executor.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "baseline_cases.h"
#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/pair_set.h"
#include "cdbench/pipeline/pipeline.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

inline constexpr const char* kExamplePipeline = "example-sap";

// The baselines' scenes and the extremes (prefixed: both lists have a giants_10).
inline std::vector<BaselineCase> example_cases() {
  std::vector<BaselineCase> cases = baseline_cases();
  for (BaselineCase c : extreme_cases()) {
    c.name = "extreme_" + c.name;
    cases.push_back(std::move(c));
  }
  return cases;
}

// Every frame of `scene`, and again with --skip-adjacent where triangles share vertices
// (in soups of separate triangles it changes nothing), from a pair buffer a quarter pair a
// triangle large, so frames with many pairs must grow it and run their query again.
inline void check_example_pipeline(const std::string& device, const SceneFrames& scene) {
  const bool shared_vertices = scene.topology.num_vertices < 3 * scene.topology.faces.size();
  for (bool skip_adjacent : {false, true}) {
    if (skip_adjacent && !shared_vertices) continue;
    PipelineConfig cfg;
    cfg.name = kExamplePipeline;
    cfg.device = device;
    cfg.skip_adjacent = skip_adjacent;
    cfg.capacity.pairs_per_triangle = 0.25;
    auto p = make_pipeline(cfg);
    p->set_topology(scene.topology);
    for (uint32_t f = 0; f < scene.frames.size(); ++f) {
      const std::string where = (skip_adjacent ? "skip-adjacent frame " : "frame ") + std::to_string(f);
      const FrameStats s = p->run_frame(scene.frames[f]);
      const std::vector<PrimPair> expected = sweep_oracle_pairs(scene.topology, scene.frames[f], skip_adjacent);
      EXPECT_EQ(s.pairs, expected.size()) << where;
      EXPECT_EQ(s.op, "sort") << where;
      const PairSetDiff d = diff_pair_sets(expected, p->sorted_pairs());
      EXPECT_TRUE(d.equal()) << where << ": " << d.missing_count << " missing, " << d.unexpected_count
                             << " unexpected of " << expected.size();
    }
  }
}

}  // namespace cdb::test
