#pragma once
// Name -> pipeline on one executor, as the table (pipeline/pipeline_kinds.h) says. Each
// backend (host_backend.cpp, cuda_backend.cu) instantiates this once. The library's one way
// into baselines/ (broad_phase.h and the standalone methods' pipelines, which only this
// file includes).
#include <memory>

#include "example/example_sap_pipeline.h"
#include "pipeline/broad_phase.h"
#include "pipeline/front_pipeline.h"
#include "pipeline/pipeline_kinds.h"

namespace cdb {

template <class Exec, class Timer>
std::unique_ptr<Pipeline> make_pipeline_on(const PipelineConfig& c) {
  const PipelineKind* kind = find_pipeline_kind(c.name);
  if (!kind) return nullptr;
  if (const auto* method = std::get_if<BroadPhaseMethod>(&kind->builds))
    return std::make_unique<BroadPhase<Exec, Timer>>(c, *method);
  if (const auto* method = std::get_if<StandaloneMethod>(&kind->builds)) {
    switch (*method) {
      case StandaloneMethod::example_sap:
        return std::make_unique<ExampleSap<Exec, Timer>>(c);
    }
    return nullptr;
  }
  return std::make_unique<FrontPipeline<Exec, Timer>>(c, std::get<FrontStrategy>(kind->builds));
}

}  // namespace cdb
