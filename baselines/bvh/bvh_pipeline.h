#pragma once
// The bvh baseline: the ordered LBVH built on the first frame (and every --rebuild-every
// frames), refitted otherwise, and traversed whole every frame by the escape-index
// self-query (and the cross query of a split scene); no fronts. A split scene's rigid tree
// is only refitted after its build (docs/design.md "Deformable and rigid objects").
#include <string>

#include "cdbench/bvh/cross_query.h"
#include "cdbench/bvh/self_query.h"
#include "cdbench/pipeline/pair_pipeline.h"

namespace cdb {

template <class Exec, class Timer>
class BvhPipeline final : public QueryPipeline<Exec, Timer> {
 public:
  explicit BvhPipeline(const PipelineConfig& config)
      : QueryPipeline<Exec, Timer>(config), bvh_(this->exec_), rigid_bvh_(this->exec_, "rigid_bvh") {}

 private:
  void reserve(uint32_t) override {
    bvh_.refit_top_max_leaves = rigid_bvh_.refit_top_max_leaves = this->config_.tree.refit_top_leaves;
    bvh_.refit_levels = rigid_bvh_.refit_levels = switched_on(this->config_.tree.refit_levels, Exec::is_device);
    bvh_.reserve(this->exec_, this->mesh_.deformable().count);
    rigid_bvh_.reserve(this->exec_, this->mesh_.rigid().count);
  }

  bool builds_trees() const override { return true; }

  std::string prepare(const MeshView& mesh) override {
    const uint64_t frame = this->frame();
    const bool rebuild = rebuild_due(frame, this->config_.tree.rebuild_every);
    if (!rebuild && !refit_due(frame, this->config_.tree.refit_every)) return "stale";
    update_hierarchy(this->exec_, this->timer_, rigid_bvh_, mesh, this->mesh_.rigid(),
                     this->mesh_.split().rigid_tree_builds(frame == 0, rebuild),
                     this->config_.tree.morton_bits, false, this->mesh_.face_object());
    return update_hierarchy(this->exec_, this->timer_, bvh_, mesh, this->mesh_.deformable(), rebuild,
                            this->config_.tree.morton_bits, false, nullptr, this->mesh_.pieces());
  }

  // The traversals the scene's queries need (all of the one tree's pairs when unsplit).
  void query(const MeshView&) override {
    const ObjectSplit& split = this->mesh_.split();
    if (split.deformable_self) self_query(this->exec_, bvh_.view(), this->pairs_.sink());
    if (split.cross) cross_query(this->exec_, bvh_.view(), rigid_bvh_.view(), this->pairs_.sink());
    if (split.rigid_self) self_query(this->exec_, rigid_bvh_.view(), this->pairs_.sink());
  }

  Lbvh<Exec> bvh_;        // T_D: the deformable faces, or every face of an unsplit scene
  Lbvh<Exec> rigid_bvh_;  // T_R: the rigid faces and the split's deformable ones (empty unless needed)
};

}  // namespace cdb
