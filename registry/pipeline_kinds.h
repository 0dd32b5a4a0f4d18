#pragma once
// The registry: the one place above the engine (lib/) and the baselines that names every
// pipeline. Every name and what it builds is one row of the table (pipeline_kinds.cpp); the
// factory (pipeline_factory.h), pipeline_names(), config_conservative() and the command
// line's help read it, so a new method is its own folder plus a row (and, for a baseline,
// its case in pipeline_factory.h).
#include <string>
#include <variant>
#include <vector>

#include "cdbench/pipeline/frame_plan.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

// The pipelines without fronts, each a QueryPipeline class of its own (pipeline_factory.h
// makes it; docs/extending.md "Adding a pipeline").
enum class BaselineMethod {
  bvh,          // baselines/bvh/bvh_pipeline.h
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

// Pipelines the factory knows, in the order verify runs them (the table above).
const std::vector<std::string>& pipeline_names();

// The oracle pipeline's name.
inline const char* oracle_pipeline() { return "brute"; }

std::unique_ptr<Pipeline> make_pipeline(const PipelineConfig& config);

// Per-backend factories (registry/host_backend.cpp, registry/cuda_backend.cu).
std::unique_ptr<Pipeline> make_host_pipeline(const PipelineConfig& config);
std::unique_ptr<Pipeline> make_cuda_pipeline(const PipelineConfig& config);

// Whether the config can miss pairs of the exact box-overlap set (refit_every > 1 on a
// pipeline that refits a hierarchy).
bool config_conservative(const PipelineConfig& config);

}  // namespace cdb
