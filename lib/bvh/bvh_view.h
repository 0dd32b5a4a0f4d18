#pragma once
#include <cstdint>

#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/vec.h"

namespace cdb {

// An ordered LBVH as kernels see it. Leaves are stored apart from internal nodes, both
// with SoA boxes (one 16-byte load per corner) that carry the links a traversal follows in
// their spare lanes (node_ref.h). Leaves are in Morton order; internal nodes are in
// depth-first (pre-)order, so the root is node 0 and an internal left child of node k is
// node k + 1. Node k covers leaves [node_first[k], node_last[k]].
struct BvhView {
  uint32_t num_leaves;
  const vec4f* leaf_lo;
  const vec4f* leaf_hi;
  const vec4f* node_lo;
  const vec4f* node_hi;
  const uint32_t* node_right;
  const uint32_t* node_first;
  const uint32_t* node_last;

  CDB_HD_INLINE uint32_t root() const {
    return num_leaves == 0 ? kNoNode : num_leaves == 1 ? leaf_ref(0) : 0u;
  }
};

}  // namespace cdb
