#pragma once
// The frame loop shared by the pipelines of this file, written once over the executor:
// upload vertices, update or rebuild the ordered LBVH (or the sweep's sorted boxes, or the
// hash grid), run the query into a growing pair buffer. One host synchronization a frame,
// the pair-count read-back; the hash adds one, its entry count.
#include <algorithm>
#include <string>
#include <vector>

#include "bruteforce/brute_force.h"
#include "bvh/build.h"
#include "bvh/lbvh.h"
#include "bvh/order.h"
#include "bvh/refit.h"
#include "bvh/self_query.h"
#include "core/error.h"
#include "core/pair_sink.h"
#include "hash/spatial_hash.h"
#include "pipeline/pipeline.h"
#include "sweep/sweep.h"

namespace cdb {

enum class BroadPhaseMethod {
  bvh,        // build once (and every rebuild_every frames), refit otherwise
  reference,  // rebuild every frame
  sweep,      // sort-and-sweep along the axis of largest centroid variance, every frame
  hash,       // uniform-grid spatial hashing (kDet style), every frame
  brute,      // O(N^2) oracle
};

template <class Exec, class Timer>
class BroadPhase final : public Pipeline {
 public:
  BroadPhase(const PipelineConfig& config, BroadPhaseMethod method)
      : config_(config),
        method_(method),
        timer_(exec_),
        bvh_(exec_),
        sweep_(exec_),
        hash_(exec_) {
    MemoryResource& mr = exec_.memory();
    vertices_.bind(mr, "mesh.vertices");
    faces_.bind(mr, "mesh.faces");
    pairs_.bind(mr, "pairs");
    pair_count_.bind(mr, "pair_count");
    prim_lo_.bind(mr, "brute.lo");
    prim_hi_.bind(mr, "brute.hi");
  }

  void set_topology(const Topology& topology) override {
    num_vertices_ = topology.num_vertices;
    num_faces_ = static_cast<uint32_t>(topology.faces.size());
    if (topology.faces.size() > kMaxLeaves) fail("scene has more triangles than 2^31-1");
    vertices_.reserve(num_vertices_);
    faces_.reserve(num_faces_);
    exec_.copy_from_host(faces_.data(), topology.faces.data(), num_faces_);
    pair_count_.reserve(1);
    pairs_.reserve(std::max<size_t>(1024, size_t(config_.pairs_per_triangle * num_faces_)));
    switch (method_) {
      case BroadPhaseMethod::brute:
        prim_lo_.reserve(num_faces_);
        prim_hi_.reserve(num_faces_);
        break;
      case BroadPhaseMethod::sweep:
        sweep_.reserve(exec_, num_faces_);
        break;
      case BroadPhaseMethod::hash:
        hash_.reserve(exec_, num_faces_);
        break;
      case BroadPhaseMethod::bvh:
      case BroadPhaseMethod::reference:
        bvh_.reserve(exec_, num_faces_);
        break;
    }
    frame_ = 0;
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    if (vertices.size() != num_vertices_)
      fail("frame has " + std::to_string(vertices.size()) + " vertices, topology has " +
           std::to_string(num_vertices_));
    FrameStats stats;
    timer_.start_frame();
    timer_.start(Phase::upload);
    exec_.copy_from_host(vertices_.data(), vertices.data(), num_vertices_);
    timer_.stop(Phase::upload);
    const MeshView mesh{vertices_.data(), faces_.data(), num_faces_};
    stats.op = update_hierarchy(mesh);
    stats.query_reruns = query(mesh);
    stats.pairs = last_count_;
    for (size_t p = 0; p < kPhaseCount; ++p) stats.phase_ms[p] = timer_.phase_ms(Phase(p));
    stats.total_ms = timer_.frame_ms() - stats.phase_ms[size_t(Phase::upload)];
    ++frame_;
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override {
    std::vector<PrimPair> out(last_count_);
    exec_.copy_to_host(out.data(), pairs_.data(), last_count_);
    std::sort(out.begin(), out.end(),
              [](PrimPair a, PrimPair b) { return pair_key(a) < pair_key(b); });
    return out;
  }

  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  std::string update_hierarchy(const MeshView& mesh) {
    if (method_ == BroadPhaseMethod::brute) {
      timer_.start(Phase::boxes);
      exec_.for_each_n(num_faces_, FaceBoxFn{mesh, prim_lo_.data(), prim_hi_.data()});
      timer_.stop(Phase::boxes);
      return "none";
    }
    if (method_ == BroadPhaseMethod::sweep) {
      timer_.start(Phase::boxes);
      sweep_boxes(exec_, sweep_, mesh);
      timer_.stop(Phase::boxes);
      timer_.start(Phase::build);
      sweep_sort(exec_, sweep_, num_faces_);
      timer_.stop(Phase::build);
      return "sort";
    }
    if (method_ == BroadPhaseMethod::hash) {
      timer_.start(Phase::boxes);
      hash_boxes(exec_, hash_, mesh);
      timer_.stop(Phase::boxes);
      timer_.start(Phase::build);
      const uint32_t regrids = hash_build(exec_, hash_, num_faces_);
      timer_.stop(Phase::build);
      return regrids == 0 ? "hash" : "rehash";
    }
    const bool rebuild = method_ == BroadPhaseMethod::reference || frame_ == 0 ||
                         (config_.rebuild_every > 0 && frame_ % config_.rebuild_every == 0);
    if (!rebuild) {
      timer_.start(Phase::refit);
      refit(exec_, bvh_, mesh);
      timer_.stop(Phase::refit);
      return "refit";
    }
    timer_.start(Phase::build);
    build_hierarchy(exec_, bvh_, mesh, config_.morton_bits);
    timer_.stop(Phase::build);
    timer_.start(Phase::order);
    order_depth_first(exec_, bvh_);
    timer_.stop(Phase::order);
    return "build";
  }

  // Runs the query; if the pair buffer was too small, grows it to the measured need and
  // runs again. Returns how many re-runs that took.
  uint32_t query(const MeshView&) {
    uint32_t reruns = 0;
    for (;;) {
      timer_.start(Phase::query);
      exec_.fill(pair_count_.data(), 1, 0ull);
      const PairSink sink{pairs_.data(), pair_count_.data(), pairs_.capacity()};
      switch (method_) {
        case BroadPhaseMethod::brute:
          brute_force_pairs(exec_, num_faces_, prim_lo_.data(), prim_hi_.data(), sink);
          break;
        case BroadPhaseMethod::sweep:
          sweep_pairs(exec_, sweep_, num_faces_, sink);
          break;
        case BroadPhaseMethod::hash:
          hash_pairs(exec_, hash_, num_faces_, sink);
          break;
        case BroadPhaseMethod::bvh:
        case BroadPhaseMethod::reference:
          self_query(exec_, bvh_.view(), sink);
          break;
      }
      timer_.stop(Phase::query);
      timer_.stop_frame();
      unsigned long long count = 0;
      exec_.copy_to_host(&count, pair_count_.data(), 1);
      last_count_ = count;
      if (count <= pairs_.capacity()) return reruns;
      pairs_.reserve(size_t(count + count / 4));
      ++reruns;
    }
  }

  PipelineConfig config_;
  BroadPhaseMethod method_;
  Exec exec_;
  Timer timer_;
  Lbvh<Exec> bvh_;
  SweepAndPrune<Exec> sweep_;
  SpatialHash<Exec> hash_;
  Array<vec3f> vertices_;
  Array<Tri> faces_;
  Array<PrimPair> pairs_;
  Array<unsigned long long> pair_count_;
  Array<vec4f> prim_lo_, prim_hi_;
  uint32_t num_vertices_ = 0, num_faces_ = 0;
  uint64_t frame_ = 0;
  uint64_t last_count_ = 0;
};

template <class Exec, class Timer>
std::unique_ptr<Pipeline> make_broad_phase(const PipelineConfig& config) {
  if (config.name == "bvh")
    return std::make_unique<BroadPhase<Exec, Timer>>(config, BroadPhaseMethod::bvh);
  if (config.name == "reference")
    return std::make_unique<BroadPhase<Exec, Timer>>(config, BroadPhaseMethod::reference);
  if (config.name == "sweep")
    return std::make_unique<BroadPhase<Exec, Timer>>(config, BroadPhaseMethod::sweep);
  if (config.name == "hash")
    return std::make_unique<BroadPhase<Exec, Timer>>(config, BroadPhaseMethod::hash);
  if (config.name == "brute")
    return std::make_unique<BroadPhase<Exec, Timer>>(config, BroadPhaseMethod::brute);
  return nullptr;
}

}  // namespace cdb
