#pragma once
// The refit's tiling (bvh/refit.h, bvh/refit_top.h, bvh/refit_index.h): leaves per tile, which
// nodes span tiles, and how large a tree refits its top (the nodes spanning tiles) in one
// block.
#include <cstdint>

#include "core/hd.h"

namespace cdb {

// Most leaves a refit tile holds: one block of the tile kernel. The tiles are treelets, the
// largest subtrees of at most kRefitTile leaves (bvh/refit_index.h). 512 refits faster than 256 (docs/design.md
// "Constants and their measurements"); the tile's shared memory (34 KB) stays under the
// static limit, 1024 would not.
inline constexpr uint32_t kRefitTile = 512;
// Default of Lbvh::refit_top_max_leaves (--refit-top-leaves): the largest tree whose top
// refits in one block, past which handing the top over between blocks is faster
// (docs/results.md has the A/B behind it).
inline constexpr uint32_t kRefitTopMaxLeaves = 1u << 15;
// The most --refit-top-leaves may be: past 2^24 leaves one block is never the faster way.
inline constexpr uint32_t kRefitTopLeavesLimit = 1u << 24;
// Spanning nodes the block keeps in shared memory; the rest live in global memory. Over
// treelets about 0.3% of the internal nodes span tiles (103 on the 32K cloth), so a default
// tree keeps every slot here; 384 slots measured no faster (docs/experiments.md).
inline constexpr uint32_t kRefitTopSharedSlots = 1536;

// Whether node [first, last] spans tiles: with treelet tiles, whether it has more leaves than
// a tile holds (a node with fewer lies inside the treelet that holds it).
CDB_HD_INLINE bool spans_tiles(uint32_t first, uint32_t last) { return last - first >= kRefitTile; }

}  // namespace cdb
