#pragma once
// Refit: new leaf boxes from the current vertices, then one thread per leaf climbs; the
// second thread to reach a node (atomic counter, acquire/release) merges both children.
// Topology and depth-first order are kept.
#include <cstdint>

#include "exec/balance.h"
#include "bvh/lbvh.h"
#include "bvh/node_ref.h"
#include "core/atomics.h"
#include "geometry/mesh.h"

namespace cdb {

struct RefitFn {
  MeshView mesh;
  const uint32_t* leaf_prim;
  const uint32_t* leaf_parent;
  const uint32_t* node_left;
  const uint32_t* node_right;
  const uint32_t* node_parent;
  vec4f* leaf_lo;
  vec4f* leaf_hi;
  vec4f* node_lo;
  vec4f* node_hi;
  uint32_t* flag;

  CDB_HD void operator()(uint32_t i) const {
    vec4f lo, hi;
    face_box(mesh, leaf_prim[i], lo, hi);
    leaf_lo[i] = lo;
    leaf_hi[i] = hi;
    uint32_t child = leaf_ref(i);
    uint32_t p = leaf_parent[i];
    while (p != kNoNode) {
      if (atomic_add_acq_rel(&flag[p], 1u) == 0) return;
      const uint32_t l = node_left[p];
      const uint32_t sibling = l == child ? node_right[p] : l;
      const vec4f slo = is_leaf(sibling) ? load_coherent(&leaf_lo[ref_index(sibling)])
                                         : load_coherent(&node_lo[sibling]);
      const vec4f shi = is_leaf(sibling) ? load_coherent(&leaf_hi[ref_index(sibling)])
                                         : load_coherent(&node_hi[sibling]);
      lo = {min_of(lo.x, slo.x), min_of(lo.y, slo.y), min_of(lo.z, slo.z), 0};
      hi = {max_of(hi.x, shi.x), max_of(hi.y, shi.y), max_of(hi.z, shi.z), 0};
      node_lo[p] = lo;
      node_hi[p] = hi;
      child = p;
      p = node_parent[p];
    }
  }
};

template <class Exec>
void refit(Exec& exec, Lbvh<Exec>& bvh, const MeshView& mesh) {
  const uint32_t n = bvh.num_leaves;
  if (n == 0) return;
  if (n > 1) exec.fill(bvh.refit_flag.data(), n - 1, 0u);
  exec.for_each_n(n, RefitFn{mesh, bvh.leaf_prim.data(), bvh.leaf_parent.data(),
                             bvh.node_left.data(), bvh.node_right.data(), bvh.node_parent.data(),
                             bvh.leaf_lo.data(), bvh.leaf_hi.data(), bvh.node_lo.data(),
                             bvh.node_hi.data(), bvh.refit_flag.data()},
                  Balance::uneven);
}

}  // namespace cdb
