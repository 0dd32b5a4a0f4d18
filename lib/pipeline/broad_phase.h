#pragma once
// Pipelines without fronts, written once over the executor: upload vertices, update or
// rebuild the ordered LBVH, run the self query into a growing pair buffer. One host
// synchronization a frame: the pair-count read-back.
#include <algorithm>
#include <string>
#include <vector>

#include "bruteforce/brute_force.h"
#include "bvh/self_query.h"
#include "pipeline/device_mesh.h"
#include "pipeline/pipeline.h"

namespace cdb {

enum class BroadPhaseMethod {
  bvh,    // build once (and every rebuild_every frames), refit otherwise
  brute,  // O(N^2) oracle
};

template <class Exec, class Timer>
class BroadPhase final : public Pipeline {
 public:
  BroadPhase(const PipelineConfig& config, BroadPhaseMethod method)
      : config_(config), method_(method), timer_(exec_), mesh_(exec_), bvh_(exec_), pairs_(exec_) {
    prim_lo_.bind(exec_.memory(), "brute.lo");
    prim_hi_.bind(exec_.memory(), "brute.hi");
  }

  void set_topology(const Topology& topology) override {
    mesh_.set_topology(exec_, topology);
    const uint32_t n = mesh_.num_faces();
    pairs_.reserve(size_t(config_.pairs_per_triangle * n));
    if (method_ == BroadPhaseMethod::brute) {
      prim_lo_.reserve(n);
      prim_hi_.reserve(n);
    } else {
      bvh_.reserve(exec_, n);
    }
    frame_ = 0;
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    FrameStats stats;
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    if (method_ == BroadPhaseMethod::brute) {
      timer_.start(Phase::boxes);
      exec_.for_each_n(mesh.num_faces, FaceBoxFn{mesh, prim_lo_.data(), prim_hi_.data()});
      timer_.stop(Phase::boxes);
      stats.op = "none";
    } else {
      const bool rebuild = frame_ == 0 || (config_.rebuild_every > 0 && frame_ % config_.rebuild_every == 0);
      stats.op = update_hierarchy(exec_, timer_, bvh_, mesh, rebuild, config_.morton_bits);
    }
    do {
      timer_.start(Phase::query);
      pairs_.reset_counters(exec_);
      if (method_ == BroadPhaseMethod::brute)
        brute_force_pairs(exec_, mesh.num_faces, prim_lo_.data(), prim_hi_.data(), pairs_.sink());
      else
        self_query(exec_, bvh_.view(), pairs_.sink());
      timer_.stop(Phase::query);
      timer_.stop_frame();
      pairs_.read_counters(exec_);
    } while (pairs_.grow_if_needed() && ++stats.query_reruns);
    stats.pairs = pairs_.count();
    record_timings(timer_, stats);
    ++frame_;
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  PipelineConfig config_;
  BroadPhaseMethod method_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  Lbvh<Exec> bvh_;
  PairBuffer<Exec> pairs_;
  Array<vec4f> prim_lo_, prim_hi_;
  uint64_t frame_ = 0;
};

}  // namespace cdb
