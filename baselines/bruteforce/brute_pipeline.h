#pragma once
// The oracle as a pipeline: every pair of triangle boxes tested, O(N^2), every frame.
#include <string>

#include "baselines/bruteforce/brute_force.h"
#include "baselines/common/face_boxes.h"
#include "cdbench/pipeline/pair_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
class BrutePipeline final : public QueryPipeline<Exec, Timer> {
 public:
  explicit BrutePipeline(const PipelineConfig& config) : QueryPipeline<Exec, Timer>(config), boxes_(this->exec_.memory(), "brute") {}

 private:
  void reserve(uint32_t faces) override { boxes_.reserve_faces(faces); }
  std::string prepare(const MeshView& mesh) override {
    this->timed(Phase::boxes, [&] { face_boxes(this->exec_, boxes_, mesh); });
    return "none";
  }
  void query(const MeshView& mesh) override {
    brute_force_pairs(this->exec_, mesh.num_faces, boxes_.lo.data(), boxes_.hi.data(), this->pairs_.sink());
  }

  FaceBoxes boxes_;
};

}  // namespace cdb
