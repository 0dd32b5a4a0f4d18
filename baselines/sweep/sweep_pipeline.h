#pragma once
// Sort-and-sweep as a pipeline: boxes, the sort along the axis of largest centroid
// variance, then the sweep, every frame (sweep.h).
#include <string>

#include "cdbench/pipeline/pair_pipeline.h"
#include "baselines/sweep/sweep.h"

namespace cdb {

template <class Exec, class Timer>
class SweepPipeline final : public QueryPipeline<Exec, Timer> {
 public:
  explicit SweepPipeline(const PipelineConfig& config) : QueryPipeline<Exec, Timer>(config), sweep_(this->exec_) {}

 private:
  void reserve(uint32_t faces) override { sweep_.reserve(this->exec_, faces); }
  std::string prepare(const MeshView& mesh) override {
    this->timed(Phase::boxes, [&] { sweep_boxes(this->exec_, sweep_, mesh); });
    this->timed(Phase::build, [&] { sweep_sort(this->exec_, sweep_, mesh.num_faces); });
    return "sort";
  }
  void query(const MeshView& mesh) override { sweep_pairs(this->exec_, sweep_, mesh.num_faces, this->pairs_.sink()); }

  SweepAndPrune<Exec> sweep_;
};

}  // namespace cdb
