#pragma once
// What every pipeline holds and does alike: its executor and timer, the mesh on the executor
// (its boxes follow every box option), and the pair buffer, which applies --skip-adjacent and
// declared queries as pairs are emitted. FrontPipeline (pipeline/front_pipeline.h) builds on
// it; the baselines build on QueryPipeline below, which adds their frame loop.
#include <cstddef>
#include <string>
#include <vector>

#include "cdbench/pipeline/device_mesh.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

// What a pipeline without extra counters reads back at its frame's end: the pair count.
struct PairCounters {
  unsigned long long pairs;
};

template <class Exec, class Timer, class Counters>
class PairPipeline : public Pipeline {
 public:
  using Pipeline::run_frame;
  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  ResidentPairs resident_pairs() const override { return {pairs_.data(), size_t(pairs_.count())}; }
  const MemoryStats& memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 protected:
  explicit PairPipeline(const PipelineConfig& config)
      : Pipeline(config.boxes),
        config_(config),
        exec_(ExecOptions{config.launch.dependent_launch}),
        timer_(exec_, config.launch.phase_timing),
        mesh_(exec_),
        pairs_(exec_) {
    mesh_.set_box_knobs(config_);
    if (config_.tree.refit_every == 0) fail("--refit-every must be at least 1");
  }

  // set_topology's part every pipeline shares: the mesh, the pair filters and the pair
  // buffer sized per triangle; for a pipeline that builds trees, T_D's pieces
  // (--build-pieces). Returns the face count.
  uint32_t set_mesh(const Topology& topology, bool builds_trees = false) {
    restart_rounding();
    mesh_.set_topology(exec_, topology, config_.tree.split);
    if (builds_trees)
      mesh_.set_pieces(exec_, topology, config_.tree.build_pieces, config_.tree.morton_bits);
    pairs_.skip_adjacent(config_.skip_adjacent ? mesh_.face_vertices() : nullptr);
    pairs_.filter_queries(mesh_.face_object(), mesh_.partners());
    pairs_.reserve(size_t(config_.capacity.pairs_per_triangle * mesh_.num_faces()));
    return mesh_.num_faces();
  }

  // Runs `work` as phase p of the frame's timing.
  template <class F>
  void timed(Phase p, F&& work) { time_phase(timer_, p, work); }

  PipelineConfig config_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  PairBuffer<Exec, Counters> pairs_;
};

// A pipeline whose frame is: upkeep of its structure (prepare), then a query into the pair
// buffer, read back once; a frame whose pairs did not fit (or whose structure, in settle,
// says its plan was outgrown) runs its query again. Every buffer is sized in
// reserve(faces), before the first frame; frames allocate nothing but counted growth.
template <class Exec, class Timer, class Counters = PairCounters>
class QueryPipeline : public PairPipeline<Exec, Timer, Counters> {
  using Base = PairPipeline<Exec, Timer, Counters>;

 public:
  using Base::run_frame;
  void set_topology(const Topology& topology) final {
    reserve(this->set_mesh(topology, builds_trees()));
    frame_ = 0;
    this->exec_.sync();
  }

  FrameStats run_frame(const FrameVertices& vertices) final {
    FrameStats stats;
    this->pairs_.reserve_ahead();
    const MeshView mesh = begin_frame(this->exec_, this->timer_, this->mesh_, vertices);
    stats.op = prepare(mesh);
    for (;;) {
      build(mesh);
      this->timed(Phase::query, [&] {
        this->pairs_.reset_counters(this->exec_);
        query(mesh);
      });
      this->timer_.stop_frame();
      const Counters& c = this->pairs_.read_counters(this->exec_);
      const bool settled = settle(c, stats);
      if (!this->pairs_.grow_if_needed() && settled) break;
      ++stats.timing.query_reruns;
    }
    stats.pairs = this->pairs_.count();
    record_timings(this->timer_, stats);
    ++frame_;
    return stats;
  }

 protected:
  using Base::Base;
  // Buffers for `faces` triangles.
  virtual void reserve(uint32_t faces) = 0;
  // Whether the pipeline builds hierarchies over the mesh (its tree options apply).
  virtual bool builds_trees() const { return false; }
  // The frame's upkeep before its query (boxes, sort, build, refit); returns what ran.
  virtual std::string prepare(const MeshView& mesh) = 0;
  // Before each run of the query: a structure that settle found outgrown is built again.
  virtual void build(const MeshView&) {}
  // The query into the pair buffer (PairPipeline::pairs_).
  virtual void query(const MeshView& mesh) = 0;
  // After the read-back: false if the structure must be rebuilt and the query run again
  // (then it may say so in stats.op).
  virtual bool settle(const Counters&, FrameStats&) { return true; }
  // Frames since set_topology.
  uint64_t frame() const { return frame_; }

 private:
  uint64_t frame_ = 0;
};

}  // namespace cdb
