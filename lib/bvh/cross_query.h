#pragma once
// Stackless query of one tree's leaves against another tree (the D-R traversal of a split
// scene, docs/design.md "Deformable and rigid objects"): leaf i of the query tree starts at
// the other tree's root, an overlapping internal node descends to its left child, anything
// else jumps to its escape index. The trees hold disjoint faces, so every overlapping leaf
// is a pair, reported once, with no i < j rule.
#include <cstdint>

#include "cdbench/bvh/bvh_view.h"
#include "cdbench/bvh/traverse.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/balance.h"

namespace cdb {

struct CrossQueryFn {
  BvhView query;
  BvhView tree;
  PairSink sink;
  CDB_HD void operator()(uint32_t i) const {
    const NodeBox b = query.leaf_box[i];
    const vec4f &lo = b.lo, &hi = b.hi;
    const uint32_t prim = lane_link(hi.w);
    traverse(tree, lo, hi, tree.root(), kNoNode, [&](uint32_t other) { sink.emit(prim, other); });
  }
};

template <class Exec>
void cross_query(Exec& exec, const BvhView& query, const BvhView& tree, const PairSink& sink) {
  exec.for_each_n(query.num_leaves, CrossQueryFn{query, tree, sink}, Balance::uneven);
}

}  // namespace cdb
