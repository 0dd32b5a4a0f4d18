#pragma once
// The refit's tiling (bvh/refit.h, bvh/refit_top.h, bvh/refit_index.h): leaves per tile, which
// nodes span tiles, and how large a tree refits its top (the nodes spanning tiles) in one
// block.
#include <cstdint>

#include "cdbench/core/hd.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

// A refit tile holds at most kRefitTile leaves (exec/tuning.h): one block of the tile
// kernel. The tiles are treelets, the largest subtrees of at most that many leaves
// (bvh/refit_index.h). Trees of up to kRefitTopMaxLeaves leaves (the default of
// Lbvh::refit_top_max_leaves, --refit-top-leaves) refit their top in one block, which keeps
// kRefitTopSharedSlots spanning nodes in shared memory.

// The most --refit-top-leaves may be: past 2^24 leaves one block is never the faster way.
inline constexpr uint32_t kRefitTopLeavesLimit = 1u << 24;

// Whether node [first, last] spans tiles: with treelet tiles, whether it has more leaves than
// a tile holds (a node with fewer lies inside the treelet that holds it).
CDB_HD_INLINE bool spans_tiles(uint32_t first, uint32_t last) { return last - first >= kRefitTile; }

}  // namespace cdb
