#pragma once
// A node's or a leaf's box as the tree stores it: both corners side by side, with the links
// a traversal follows in their spare lanes (node_ref.h).
#include "cdbench/core/vec.h"

namespace cdb {

// One box is one aligned 32-byte sector. A traversal gathers boxes by index, scattered over
// the tree, and with the corners in two arrays each box cost two sectors in two cache lines
// (the 1M cloth's preserve waited on those gathered loads: docs/results.md).
struct alignas(32) NodeBox {
  vec4f lo, hi;
};

}  // namespace cdb
