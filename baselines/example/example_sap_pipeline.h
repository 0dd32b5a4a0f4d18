#pragma once
// EXAMPLE (docs/extending.md): the Pipeline that runs example_sap.h on one executor. What
// every frame loop needs comes from QueryPipeline (pipeline/pair_pipeline.h): the mesh on
// the executor (its boxes follow every box option), the frame's upload, timing and one
// read-back, and the pair buffer, which applies --skip-adjacent and declared queries as
// pairs are emitted and grows, with the query run again, when a frame's pairs outgrow it.
// A method fills in four steps: reserve, prepare, query, and optionally build/settle. The
// boxes and their sort are the baselines' (common/sorted_boxes.h); the walk is the method's.
#include <string>

#include "baselines/example/example_sap.h"
#include "cdbench/pipeline/pair_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
class ExampleSap final : public QueryPipeline<Exec, Timer> {
 public:
  explicit ExampleSap(const PipelineConfig& config) : QueryPipeline<Exec, Timer>(config), sap_(this->exec_, "example-sap") {}

 private:
  // Every buffer is sized here, before the first frame; frames allocate nothing (a pair
  // buffer that must grow is counted and listed after the run).
  void reserve(uint32_t faces) override { sap_.reserve(this->exec_, faces); }
  // Boxes and the sort, once a frame; a query re-run after the pair buffer grew reuses them.
  std::string prepare(const MeshView& mesh) override {
    this->timed(Phase::boxes, [&] { face_boxes(this->exec_, sap_, mesh); });
    this->timed(Phase::build, [&] { sort_boxes(this->exec_, sap_, mesh.num_faces, MinX{}); });
    return "sort";
  }
  void query(const MeshView& mesh) override {
    example_sap_pairs(this->exec_, sap_, mesh.num_faces, this->pairs_.sink());
  }

  SortedBoxes<Exec> sap_;
};

}  // namespace cdb
