#pragma once
#include <cstdint>

#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

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

// The centroid of box [a, b] as a position in [0, 1]^3 of the box [lo, hi] (0.5 on a flat
// axis), every term halved so that coordinates near the float limit do not overflow.
CDB_HD_INLINE vec4f unit_centroid(const vec4f& a, const vec4f& b, const vec4f& lo, const vec4f& hi) {
  const float ex = hi.x * 0.5f - lo.x * 0.5f, ey = hi.y * 0.5f - lo.y * 0.5f, ez = hi.z * 0.5f - lo.z * 0.5f;
  const float cx = a.x * 0.5f + b.x * 0.5f, cy = a.y * 0.5f + b.y * 0.5f, cz = a.z * 0.5f + b.z * 0.5f;
  return {ex > 0 ? (cx * 0.5f - lo.x * 0.5f) / ex : 0.5f, ey > 0 ? (cy * 0.5f - lo.y * 0.5f) / ey : 0.5f,
          ez > 0 ? (cz * 0.5f - lo.z * 0.5f) / ez : 0.5f, 0};
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
