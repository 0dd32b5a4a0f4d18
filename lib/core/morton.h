#pragma once
#include <cstdint>

#include "core/hd.h"
#include "core/vec.h"

namespace cdb {

// Morton code width; the choice is a run parameter (--morton-bits).
enum class MortonBits : int { b30 = 30, b63 = 63 };

CDB_HD_INLINE uint32_t spread_bits_10(uint32_t v) {
  v = (v * 0x00010001u) & 0xFF0000FFu;
  v = (v * 0x00000101u) & 0x0F00F00Fu;
  v = (v * 0x00000011u) & 0xC30C30C3u;
  v = (v * 0x00000005u) & 0x49249249u;
  return v;
}

CDB_HD_INLINE uint64_t spread_bits_21(uint64_t v) {
  v &= 0x1fffffull;
  v = (v | v << 32) & 0x1f00000000ffffull;
  v = (v | v << 16) & 0x1f0000ff0000ffull;
  v = (v | v << 8) & 0x100f00f00f00f00full;
  v = (v | v << 4) & 0x10c30c30c30c30c3ull;
  v = (v | v << 2) & 0x1249249249249249ull;
  return v;
}

// Maps t in [0,1] to a grid cell; NaN and out-of-range values clamp (fmax/fmin drop NaN),
// so a code is always defined. Codes only steer tree quality, never correctness.
CDB_HD_INLINE uint32_t grid_cell(float t, float cells) {
  float c = t * cells;
  c = c > 0.0f ? c : 0.0f;
  c = c < cells - 1.0f ? c : cells - 1.0f;
  return static_cast<uint32_t>(c);
}

CDB_HD_INLINE uint64_t morton_code(vec4f unit, MortonBits bits) {
  if (bits == MortonBits::b30) {
    return (uint64_t(spread_bits_10(grid_cell(unit.x, 1024.0f))) << 2) |
           (uint64_t(spread_bits_10(grid_cell(unit.y, 1024.0f))) << 1) |
           uint64_t(spread_bits_10(grid_cell(unit.z, 1024.0f)));
  }
  return (spread_bits_21(grid_cell(unit.x, 2097152.0f)) << 2) |
         (spread_bits_21(grid_cell(unit.y, 2097152.0f)) << 1) |
         spread_bits_21(grid_cell(unit.z, 2097152.0f));
}

}  // namespace cdb
