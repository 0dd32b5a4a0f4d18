#pragma once
// Name -> pipeline on one executor, as the table (pipeline/pipeline_kinds.h) says. Each
// backend (host_backend.cpp, cuda_backend.cu) instantiates this once. The one way
// into baselines/: the baseline pipelines are included here only.
#include <memory>

#include "baselines/bruteforce/brute_pipeline.h"
#include "baselines/example/example_sap_pipeline.h"
#include "baselines/grid/grid_pipeline.h"
#include "baselines/hash/hash_pipeline.h"
#include "baselines/bvh/bvh_pipeline.h"
#include "cdbench/pipeline/front_pipeline.h"
#include "registry/pipeline_kinds.h"
#include "baselines/sweep/sweep_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
std::unique_ptr<Pipeline> make_baseline_on(const PipelineConfig& c, BaselineMethod method) {
  switch (method) {
    case BaselineMethod::bvh: return std::make_unique<BvhPipeline<Exec, Timer>>(c);
    case BaselineMethod::sweep: return std::make_unique<SweepPipeline<Exec, Timer>>(c);
    case BaselineMethod::grid: return std::make_unique<GridPipeline<Exec, Timer>>(c);
    case BaselineMethod::hash: return std::make_unique<HashPipeline<Exec, Timer>>(c);
    case BaselineMethod::brute: return std::make_unique<BrutePipeline<Exec, Timer>>(c);
    case BaselineMethod::example_sap: return std::make_unique<ExampleSap<Exec, Timer>>(c);
  }
  return nullptr;
}

template <class Exec, class Timer>
std::unique_ptr<Pipeline> make_pipeline_on(const PipelineConfig& c) {
  const PipelineKind* kind = find_pipeline_kind(c.name);
  if (!kind) return nullptr;
  if (const auto* method = std::get_if<BaselineMethod>(&kind->builds)) return make_baseline_on<Exec, Timer>(c, *method);
  return std::make_unique<FrontPipeline<Exec, Timer>>(c, std::get<FrontStrategy>(kind->builds));
}

}  // namespace cdb
