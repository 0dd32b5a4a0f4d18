#pragma once
// EXAMPLE (docs/extending.md): the Pipeline that runs example_sap.h on one executor. What
// every frame loop needs comes from pipeline/device_mesh.h: the mesh on the executor (its
// boxes follow every box option), the frame's upload and timing, and the pair buffer,
// which applies --skip-adjacent and declared queries as pairs are emitted and grows, with
// the query run again, when a frame's pairs outgrow it.
#include <cstddef>
#include <vector>

#include "example/example_sap.h"
#include "pipeline/device_mesh.h"
#include "pipeline/pipeline.h"

namespace cdb {

// What a frame reads back at its end, in one copy: the pair count first (PairBuffer's rule).
struct ExampleSapCounters {
  unsigned long long pairs;
};

template <class Exec, class Timer>
class ExampleSap final : public Pipeline {
 public:
  explicit ExampleSap(const PipelineConfig& config)
      : Pipeline(config.box_precision),
        config_(config),
        exec_(ExecOptions{config.dependent_launch}),
        timer_(exec_, config.phase_timing),
        mesh_(exec_),
        sap_(exec_),
        pairs_(exec_) {
    mesh_.set_box_knobs(config_);
  }

  using Pipeline::run_frame;

  // Every buffer is sized here, before the first frame; frames allocate nothing (a pair
  // buffer that must grow is counted and listed after the run).
  void set_topology(const Topology& topology) override {
    restart_rounding();
    mesh_.set_topology(exec_, topology);
    const uint32_t n = mesh_.num_faces();
    pairs_.skip_adjacent(config_.skip_adjacent ? mesh_.face_vertices() : nullptr);
    pairs_.filter_queries(mesh_.face_object(), mesh_.partners());
    pairs_.reserve(size_t(config_.pairs_per_triangle * n));
    sap_.reserve(exec_, n);
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    FrameStats stats;
    stats.op = "sort";
    pairs_.reserve_ahead();
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    timer_.start(Phase::boxes);
    example_sap_boxes(exec_, sap_, mesh);
    timer_.stop(Phase::boxes);
    timer_.start(Phase::build);
    example_sap_sort(exec_, sap_, mesh.num_faces);
    timer_.stop(Phase::build);
    // The frame's one synchronization is the counters' read-back; a frame whose pairs did
    // not fit runs its query again into the grown buffer (the sorted boxes still hold).
    for (;;) {
      timer_.start(Phase::query);
      pairs_.reset_counters(exec_);
      example_sap_pairs(exec_, sap_, mesh.num_faces, pairs_.sink());
      timer_.stop(Phase::query);
      timer_.stop_frame();
      pairs_.read_counters(exec_);
      if (!pairs_.grow_if_needed()) break;
      ++stats.query_reruns;
    }
    stats.pairs = pairs_.count();
    record_timings(timer_, stats);
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  PipelineConfig config_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  ExampleSapWorkspace<Exec> sap_;
  PairBuffer<Exec, ExampleSapCounters> pairs_;
};

}  // namespace cdb
