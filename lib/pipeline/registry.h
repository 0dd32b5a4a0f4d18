#pragma once
// Name -> pipeline on one executor. Each backend (host_backend.cpp, cuda_backend.cu)
// instantiates this once. The library's one way into baselines/ (broad_phase.h, which only
// this file includes).
#include <memory>

#include "pipeline/broad_phase.h"
#include "pipeline/front_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
std::unique_ptr<Pipeline> make_pipeline_on(const PipelineConfig& c) {
  if (c.name == "bvh") return std::make_unique<BroadPhase<Exec, Timer>>(c, BroadPhaseMethod::bvh);
  if (c.name == "sweep") return std::make_unique<BroadPhase<Exec, Timer>>(c, BroadPhaseMethod::sweep);
  if (c.name == "grid") return std::make_unique<BroadPhase<Exec, Timer>>(c, BroadPhaseMethod::grid);
  if (c.name == "hash") return std::make_unique<BroadPhase<Exec, Timer>>(c, BroadPhaseMethod::hash);
  if (c.name == "brute") return std::make_unique<BroadPhase<Exec, Timer>>(c, BroadPhaseMethod::brute);
  FrontStrategy plan;
  if (c.name == "unordered") {
    plan.ordered = false;
  } else if (c.name == "a") {
    // ordering only
  } else if (c.name == "b" || c.name == "static") {
    plan.balance = true;  // the paper's static strategy is pipeline b (§5.2, Fig. 5)
  } else if (c.name == "radix-order") {
    plan.balance = true;  // static with radix-sorted instead of histogram-sorted fronts
    plan.radix_sort = true;
  } else if (c.name == "periodic") {
    plan.balance = true;
    plan.periodic = true;
  } else if (c.name == "c" || c.name == "restructure") {
    plan.balance = true;  // pipeline c is b plus quality inspection and restructuring (§4)
    plan.restructure = true;
  } else if (c.name == "reference") {
    plan.rebuild_every_frame = true;
  } else {
    return nullptr;
  }
  return std::make_unique<FrontPipeline<Exec, Timer>>(c, plan);
}

}  // namespace cdb
