#pragma once
// Every pipeline name and what it builds, in one table (pipeline.cpp): the factory
// (pipeline/registry.h), pipeline_names(), config_conservative() and the command line's
// help read it, so a new pipeline is one row.
#include <string>
#include <variant>
#include <vector>

#include "pipeline/frame_plan.h"

namespace cdb {

// The pipelines without fronts (pipeline/broad_phase.h).
enum class BroadPhaseMethod {
  bvh,    // build once (and every rebuild_every frames), refit otherwise; a split scene's
          // rigid tree is only refitted after its build (docs/design.md)
  sweep,  // sort-and-sweep along the axis of largest centroid variance, every frame
  grid,   // uniform grid with size levels (OTG style), every frame
  hash,   // uniform-grid spatial hashing (kDet style), every frame
  brute,  // O(N^2) oracle
};

// Pipelines that are a Pipeline class of their own (docs/extending.md "Adding a
// pipeline"), one value each; the registry makes the class.
enum class StandaloneMethod {
  example_sap,  // EXAMPLE: textbook sort-and-sweep along x (baselines/example/)
};

struct PipelineKind {
  const char* name;
  const char* paper;        // the paper's name for it, or ""
  const char* description;  // one line
  std::variant<BroadPhaseMethod, FrontStrategy, StandaloneMethod> builds;
};

// In the order verify runs them.
const std::vector<PipelineKind>& pipeline_kinds();
// nullptr for an unknown name.
const PipelineKind* find_pipeline_kind(const std::string& name);

}  // namespace cdb
