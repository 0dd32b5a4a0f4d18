#pragma once
// The refit's tiling (bvh/refit.h, bvh/refit_top.h): leaves per tile, and how large a
// tree refits its top (the nodes spanning tiles) in one block.
#include <cstdint>

namespace cdb {

// Leaves per refit tile: one block of the tile kernel. 512 against 256 on the H100: refit
// cloth-wave 32 to 28 us, funnel 22 to 20, cloth-ball 50 to 48, n-body unchanged; the
// tile's shared memory (34 KB) stays under the static limit, 1024 would not.
inline constexpr uint32_t kRefitTile = 512;
// Default of Lbvh::refit_top_max_leaves (--refit-top-leaves): the largest tree whose top
// refits in one block, past which handing the top over between blocks is faster
// (docs/results.md has the A/B behind it).
inline constexpr uint32_t kRefitTopMaxLeaves = 1u << 15;
// The most --refit-top-leaves may be: past 2^24 leaves one block is never the faster way.
inline constexpr uint32_t kRefitTopLeavesLimit = 1u << 24;
// Spanning nodes the block keeps in shared memory (about 3.4% of the internal nodes span
// tiles: 1,100 at 2^15 leaves); the rest live in global memory.
inline constexpr uint32_t kRefitTopSharedSlots = 1536;

}  // namespace cdb
