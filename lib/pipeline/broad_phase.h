#pragma once
// Pipelines without fronts, written once over the executor: upload vertices, update or
// rebuild the ordered LBVH (or the sweep's sorted boxes, the uniform grid, or the hash
// grid), run the query into a growing pair buffer. One host synchronization a frame, the
// pair-count read-back (the grid's entry totals ride along with it); the hash adds one,
// its entry count.
#include <algorithm>
#include <string>
#include <vector>

#include "bruteforce/brute_force.h"
#include "bvh/cross_query.h"
#include "bvh/self_query.h"
#include "grid/uniform_grid.h"
#include "hash/spatial_hash.h"
#include "pipeline/device_mesh.h"
#include "pipeline/pipeline.h"
#include "pipeline/pipeline_kinds.h"
#include "sweep/sweep.h"

namespace cdb {

// What the baselines' frames count: the pairs, and the entries the uniform grid's cells took
// against its plan (UniformGrid::settle).
struct BroadPhaseCounters {
  unsigned long long pairs;
  unsigned long long grid_totals[kGridTotals];
};

template <class Exec, class Timer>
class BroadPhase final : public Pipeline {
 public:
  BroadPhase(const PipelineConfig& config, BroadPhaseMethod method)
      : Pipeline(config.box_precision),
        config_(config),
        method_(method),
        exec_(ExecOptions{config.dependent_launch}),
        timer_(exec_, config.phase_timing),
        mesh_(exec_),
        bvh_(exec_),
        rigid_bvh_(exec_, "rigid_bvh"),
        sweep_(exec_),
        grid_(exec_),
        hash_(exec_),
        pairs_(exec_) {
    prim_lo_.bind(exec_.memory(), "brute.lo");
    prim_hi_.bind(exec_.memory(), "brute.hi");
    mesh_.set_box_knobs(config_);
    if (config_.refit_every == 0) fail("--refit-every must be at least 1");
  }

  using Pipeline::run_frame;

  void set_topology(const Topology& topology) override {
    restart_rounding();
    mesh_.set_topology(exec_, topology);
    const uint32_t n = mesh_.num_faces();
    pairs_.skip_adjacent(config_.skip_adjacent ? mesh_.face_vertices() : nullptr);
    pairs_.filter_queries(mesh_.face_object(), mesh_.partners());
    pairs_.reserve(size_t(config_.pairs_per_triangle * n));
    switch (method_) {
      case BroadPhaseMethod::brute:
        prim_lo_.reserve(n);
        prim_hi_.reserve(n);
        break;
      case BroadPhaseMethod::sweep:
        sweep_.reserve(exec_, n);
        break;
      case BroadPhaseMethod::grid:
        grid_.reserve(exec_, n);
        break;
      case BroadPhaseMethod::hash:
        hash_.reserve(exec_, n);
        break;
      case BroadPhaseMethod::bvh:
        bvh_.refit_top_max_leaves = rigid_bvh_.refit_top_max_leaves = config_.refit_top_leaves;
        bvh_.reserve(exec_, mesh_.deformable().count);
        rigid_bvh_.reserve(exec_, mesh_.rigid().count);
        break;
    }
    frame_ = 0;
    exec_.sync();
  }

  FrameStats run_frame(const std::vector<vec3f>& vertices) override {
    FrameStats stats;
    pairs_.reserve_ahead();
    const MeshView mesh = begin_frame(exec_, timer_, mesh_, vertices);
    stats.op = prepare(mesh);
    bool build_grid = method_ == BroadPhaseMethod::grid;
    for (;;) {
      if (build_grid) {
        timer_.start(Phase::build);
        grid_build(exec_, grid_, mesh.num_faces);
        timer_.stop(Phase::build);
      }
      timer_.start(Phase::query);
      pairs_.reset_counters(exec_);
      switch (method_) {
        case BroadPhaseMethod::brute:
          brute_force_pairs(exec_, mesh.num_faces, prim_lo_.data(), prim_hi_.data(), pairs_.sink());
          break;
        case BroadPhaseMethod::sweep:
          sweep_pairs(exec_, sweep_, mesh.num_faces, pairs_.sink());
          break;
        case BroadPhaseMethod::grid:
          grid_pairs(exec_, grid_, mesh.num_faces, pairs_.sink());
          exec_.copy(pairs_.device()->grid_totals, grid_.totals.data(), kGridTotals);
          break;
        case BroadPhaseMethod::hash:
          hash_pairs(exec_, hash_, mesh.num_faces, pairs_.sink());
          break;
        case BroadPhaseMethod::bvh:
          bvh_query();
          break;
      }
      timer_.stop(Phase::query);
      timer_.stop_frame();
      const auto c = pairs_.read_counters(exec_);
      // A grid whose entries outgrew this frame's plan is rebuilt to the measured need
      // before anything else: its pair count is then incomplete.
      if (method_ == BroadPhaseMethod::grid) {
        build_grid = !grid_.settle(c.grid_totals[0], c.grid_totals[1]);
        if (build_grid) {
          stats.op = "regrid";
          ++stats.query_reruns;
          continue;
        }
      }
      if (!pairs_.grow_if_needed()) break;
      ++stats.query_reruns;
    }
    stats.pairs = pairs_.count();
    record_timings(timer_, stats);
    ++frame_;
    return stats;
  }

  std::vector<PrimPair> sorted_pairs() override { return pairs_.sorted_pairs(exec_); }
  MemoryStats memory() const override { return const_cast<Exec&>(exec_).memory().stats(); }

 private:
  // The per-frame upkeep of the method's structure; returns what ran.
  std::string prepare(const MeshView& mesh) {
    switch (method_) {
      case BroadPhaseMethod::brute:
        timer_.start(Phase::boxes);
        exec_.for_each_n(mesh.num_faces, FaceBoxFn{mesh, prim_lo_.data(), prim_hi_.data()});
        timer_.stop(Phase::boxes);
        return "none";
      case BroadPhaseMethod::sweep:
        timer_.start(Phase::boxes);
        sweep_boxes(exec_, sweep_, mesh);
        timer_.stop(Phase::boxes);
        timer_.start(Phase::build);
        sweep_sort(exec_, sweep_, mesh.num_faces);
        timer_.stop(Phase::build);
        return "sort";
      case BroadPhaseMethod::grid:
        // The build runs in the frame loop: it is re-run when its entries outgrow the plan.
        timer_.start(Phase::boxes);
        face_boxes(exec_, grid_, mesh);
        timer_.stop(Phase::boxes);
        return "grid";
      case BroadPhaseMethod::hash: {
        timer_.start(Phase::boxes);
        face_boxes(exec_, hash_, mesh);
        timer_.stop(Phase::boxes);
        timer_.start(Phase::build);
        const uint32_t regrids = hash_build(exec_, hash_, mesh.num_faces);
        timer_.stop(Phase::build);
        return regrids == 0 ? "hash" : "rehash";
      }
      case BroadPhaseMethod::bvh:
        break;
    }
    const bool rebuild = frame_ == 0 || (config_.rebuild_every > 0 && frame_ % config_.rebuild_every == 0);
    if (!rebuild && !refit_due(frame_, config_.refit_every)) return "stale";
    update_hierarchy(exec_, timer_, rigid_bvh_, mesh, mesh_.rigid(), frame_ == 0, config_.morton_bits,
                     false, mesh_.face_object());
    return update_hierarchy(exec_, timer_, bvh_, mesh, mesh_.deformable(), rebuild, config_.morton_bits);
  }

  // The traversals the scene's queries need (all of the one tree's pairs when unsplit).
  void bvh_query() {
    const ObjectSplit& split = mesh_.split();
    if (split.deformable_self) self_query(exec_, bvh_.view(), pairs_.sink());
    if (split.cross) cross_query(exec_, bvh_.view(), rigid_bvh_.view(), pairs_.sink());
    if (split.rigid_self) self_query(exec_, rigid_bvh_.view(), pairs_.sink());
  }

  PipelineConfig config_;
  BroadPhaseMethod method_;
  Exec exec_;
  Timer timer_;
  DeviceMesh<Exec> mesh_;
  Lbvh<Exec> bvh_;        // T_D: the deformable faces, or every face of an unsplit scene
  Lbvh<Exec> rigid_bvh_;  // T_R: the rigid faces (empty unless a query needs them)
  SweepAndPrune<Exec> sweep_;
  UniformGrid<Exec> grid_;
  SpatialHash<Exec> hash_;
  PairBuffer<Exec, BroadPhaseCounters> pairs_;
  Array<vec4f> prim_lo_, prim_hi_;
  uint64_t frame_ = 0;
};

}  // namespace cdb
