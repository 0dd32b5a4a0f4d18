#pragma once
// Every pipeline name and what it builds, in one table (pipeline.cpp): the factory
// (pipeline/registry.h), pipeline_names(), config_conservative() and the command line's
// help read it, so a new pipeline is one row.
#include <string>
#include <variant>
#include <vector>

#include "pipeline/frame_plan.h"

namespace cdb {

// The pipelines without fronts, each a QueryPipeline class of its own (pipeline/registry.h
// makes it; docs/extending.md "Adding a pipeline").
enum class BaselineMethod {
  bvh,          // pipeline/bvh_pipeline.h
  sweep,        // baselines/sweep/sweep_pipeline.h
  grid,         // baselines/grid/grid_pipeline.h
  hash,         // baselines/hash/hash_pipeline.h
  brute,        // baselines/bruteforce/brute_pipeline.h: the oracle
  example_sap,  // EXAMPLE: baselines/example/example_sap_pipeline.h
};

struct PipelineKind {
  const char* name;
  const char* paper;        // the paper's name for it, or ""
  const char* description;  // one line
  std::variant<BaselineMethod, FrontStrategy> builds;
};

// In the order verify runs them.
const std::vector<PipelineKind>& pipeline_kinds();
// nullptr for an unknown name.
const PipelineKind* find_pipeline_kind(const std::string& name);

}  // namespace cdb
