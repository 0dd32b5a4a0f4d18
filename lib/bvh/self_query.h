#pragma once
// Stackless self-collision query, the "leaf algorithm" (Damkjær 2007; paper Alg. 1 lines
// 1-11): leaf i starts at its own escape index, so it only ever meets leaves > i and every
// pair is reported once. An overlapping internal node descends to its left child, anything
// else jumps to its escape index.
#include <cstdint>

#include "cdbench/exec/balance.h"
#include "cdbench/bvh/bvh_view.h"
#include "cdbench/bvh/traverse.h"
#include "cdbench/core/pair_sink.h"

namespace cdb {

struct SelfQueryFn {
  BvhView bvh;
  PairSink sink;
  CDB_HD void operator()(uint32_t i) const {
    const NodeBox b = bvh.leaf_box[i];
    const vec4f &lo = b.lo, &hi = b.hi;
    const uint32_t prim = lane_link(hi.w);
    traverse(bvh, lo, hi, lane_link(lo.w), kNoNode, [&](uint32_t other) { sink.emit(prim, other); });
  }
};

template <class Exec>
void self_query(Exec& exec, const BvhView& bvh, const PairSink& sink) {
  exec.for_each_n(bvh.num_leaves, SelfQueryFn{bvh, sink}, Balance::uneven);
}

}  // namespace cdb
