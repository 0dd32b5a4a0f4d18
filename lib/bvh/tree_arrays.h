#pragma once
// The arrays of an Lbvh as its kernels see them: plain views of device (or host) pointers,
// passed by value into each kernel the way cuBQL passes its BVH, so that a kernel names
// the tree, the build scratch or the refit's index once instead of pointer by pointer.
// Lbvh::tree(), build() and refit_index() fill them.
#include <cstdint>

#include "cdbench/bvh/node_box.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

// The ordered tree (layout: bvh/bvh_view.h; link lanes: bvh/node_ref.h).
struct TreeArrays {
  NodeBox* leaf_box;
  uint32_t *leaf_prim, *leaf_parent, *leaf_escape;
  NodeBox* node_box;
  uint32_t *node_left, *node_right, *node_parent, *node_escape, *node_first, *node_last;
};

// The build-numbered tree of Apetrei's climb (bvh/build.h: internal node k is the split
// between sorted leaves k and k+1) and what the depth-first layout (bvh/order.h) keeps of
// it: each leaf's count of internal nodes it is leftmost in, its scan, the new indices.
struct BuildArrays {
  vec4f *lo, *hi;
  uint32_t *left, *right, *parent, *first, *last;
  uint32_t *other_bound, *count_log, *offset_log, *new_index;
};

// What index_refit (bvh/refit_index.h) writes per topology and the refit reads: the tiles,
// the spanning top's slots (bvh/refit_top.h) and the tiles' level tables
// (bvh/refit_levels.h).
struct RefitIndexArrays {
  // Per leaf: 1 where a treelet starts, and its scan; each tile's first leaf (n after the
  // last); the number of tiles.
  uint32_t *tile_start, *tile_scan, *tile_first, *tile_count;
  // Per internal node: 1 where it spans (null where the top is not indexed), and its scan,
  // the node's slot. [0]: slots, [1]: the deepest slot's depth.
  uint32_t *span_flag, *span_scan, *span_count;
  // Per slot: its node; parent slot | side << 31 (1: right child), kNoNode at the root; left
  // and right, the child if it does not span, else kNoNode; its node's depth, the root's 0.
  uint32_t *span_node, *span_parent, *span_child, *span_depth;
  vec4f *span_lo, *span_hi;  // boxes of the slots kept in global memory, [2 * slot + side]
  // Per split: the node; depth | left place << 10 | right place << 20; the node's left link
  // and escape, its box's lanes (node_ref.h).
  uint32_t *level_node, *level_code, *level_link;
};

}  // namespace cdb
