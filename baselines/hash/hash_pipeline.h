#pragma once
// Spatial hashing as a pipeline: boxes, the hash grid built (its entry count read back:
// the frame's second synchronization), then the pair tests per cell, every frame
// (spatial_hash.h).
#include <string>

#include "baselines/hash/spatial_hash.h"
#include "cdbench/pipeline/pair_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
class HashPipeline final : public QueryPipeline<Exec, Timer> {
 public:
  explicit HashPipeline(const PipelineConfig& config) : QueryPipeline<Exec, Timer>(config), hash_(this->exec_) {}

 private:
  void reserve(uint32_t faces) override { hash_.reserve(this->exec_, faces); }
  std::string prepare(const MeshView& mesh) override {
    this->timed(Phase::boxes, [&] { face_boxes(this->exec_, hash_, mesh); });
    uint32_t regrids = 0;
    this->timed(Phase::build, [&] { regrids = hash_build(this->exec_, hash_, mesh.num_faces); });
    return regrids == 0 ? "hash" : "rehash";
  }
  void query(const MeshView& mesh) override { hash_pairs(this->exec_, hash_, mesh.num_faces, this->pairs_.sink()); }

  SpatialHash<Exec> hash_;
};

}  // namespace cdb
