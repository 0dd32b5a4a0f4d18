#pragma once
// The uniform grid as a pipeline: boxes, then the grid built on the host's plan and queried
// (uniform_grid.h). The device's entry totals come back with the pair count; a frame whose
// entries outgrew the plan builds again to the measured need and queries again.
#include <string>

#include "baselines/grid/uniform_grid.h"
#include "cdbench/pipeline/pair_pipeline.h"

namespace cdb {

struct GridCounters {
  unsigned long long pairs;
  GridTotals grid;
};

template <class Exec, class Timer>
class GridPipeline final : public QueryPipeline<Exec, Timer, GridCounters> {
 public:
  explicit GridPipeline(const PipelineConfig& config)
      : QueryPipeline<Exec, Timer, GridCounters>(config), grid_(this->exec_) {}

 private:
  void reserve(uint32_t faces) override { grid_.reserve(this->exec_, faces); }
  std::string prepare(const MeshView& mesh) override {
    this->timed(Phase::boxes, [&] { face_boxes(this->exec_, grid_, mesh); });
    built_ = false;
    return "grid";
  }
  void build(const MeshView& mesh) override {
    if (built_) return;
    this->timed(Phase::build, [&] { grid_build(this->exec_, grid_, mesh.num_faces); });
    built_ = true;
  }
  void query(const MeshView& mesh) override {
    grid_pairs(this->exec_, grid_, mesh.num_faces, this->pairs_.sink());
    this->exec_.copy(&this->pairs_.device()->grid, grid_.totals.data(), 1);
  }
  // Pairs found on an outgrown plan are incomplete: the grid is built again first.
  bool settle(const GridCounters& c, FrameStats& stats) override {
    built_ = grid_.settle(c.grid);
    if (!built_) stats.op = "regrid";
    return built_;
  }

  UniformGrid<Exec> grid_;
  bool built_ = false;  // the grid holds this frame's boxes on a plan that fits them
};

}  // namespace cdb
