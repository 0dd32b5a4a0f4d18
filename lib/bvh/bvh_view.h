#pragma once
#include <cstdint>

#include "cdbench/bvh/node_box.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/vec.h"

namespace cdb {

// An ordered LBVH as kernels see it. Leaves are stored apart from internal nodes, both
// each box one 32-byte NodeBox (both corners in one sector, bvh/node_box.h) that carries the
// links a traversal follows in its spare lanes (node_ref.h). Leaves are in Morton order; internal nodes are in
// depth-first (pre-)order, so the root is node 0 and an internal left child of node k is
// node k + 1. Node k covers leaves [node_first[k], node_last[k]].
struct BvhView {
  uint32_t num_leaves;
  const NodeBox* leaf_box;
  const NodeBox* node_box;
  const uint32_t* node_right;
  const uint32_t* node_first;
  const uint32_t* node_last;

  CDB_HD_INLINE uint32_t root() const {
    return num_leaves == 0 ? kNoNode : num_leaves == 1 ? leaf_ref(0) : 0u;
  }
};

}  // namespace cdb
