#pragma once
// The oracle as a pipeline: every pair of triangle boxes tested, O(N^2), every frame.
#include <string>

#include "bruteforce/brute_force.h"
#include "pipeline/pair_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
class BrutePipeline final : public QueryPipeline<Exec, Timer> {
 public:
  explicit BrutePipeline(const PipelineConfig& config) : QueryPipeline<Exec, Timer>(config) {
    lo_.bind(this->exec_.memory(), "brute.lo");
    hi_.bind(this->exec_.memory(), "brute.hi");
  }

 private:
  void reserve(uint32_t faces) override {
    lo_.reserve(faces);
    hi_.reserve(faces);
  }
  std::string prepare(const MeshView& mesh) override {
    this->timed(Phase::boxes, [&] { this->exec_.for_each_n(mesh.num_faces, FaceBoxFn{mesh, lo_.data(), hi_.data()}); });
    return "none";
  }
  void query(const MeshView& mesh) override {
    brute_force_pairs(this->exec_, mesh.num_faces, lo_.data(), hi_.data(), this->pairs_.sink());
  }

  Array<vec4f> lo_, hi_;
};

}  // namespace cdb
