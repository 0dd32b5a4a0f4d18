#pragma once
// Tiles of consecutive indices for Exec::for_each_tile: tile t is [first[t], first[t + 1]),
// at most F::kTile indices, *count tiles; both arrays in the executor's memory, so a tiling
// computed on the device needs no copy to the host. On the GPU `blocks` blocks take the
// tiles in turn (block b tiles b, b + blocks, ...).
#include <cstdint>

namespace cdb {

struct Tiles {
  const uint32_t* first;
  const uint32_t* count;
  uint32_t blocks;
};

}  // namespace cdb
