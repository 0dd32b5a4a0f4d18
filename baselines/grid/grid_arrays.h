#pragma once
// The uniform grid's arrays as its kernels see them (UniformGrid::arrays): one plain view,
// passed by value, instead of each kernel naming the pointers it reads one by one.
#include <cstdint>

#include "baselines/grid/grid_geometry.h"
#include "cdbench/core/vec.h"

namespace cdb {

struct GridArrays {
  const vec4f *lo, *hi;      // the face boxes
  const GridLayout* params;  // the cell size and levels of this frame
  // Per box: its cell entries, the offset of its first, its level.
  uint32_t *counts, *offsets, *level;
  // Per level: its first sorted entry (kGridMaxLevels + 1 of them, the last the end).
  uint32_t* level_begin;
  // The (cell key, box) entries, as registered and sorted by key.
  uint64_t *keys, *sorted_keys;
  uint32_t *boxes, *sorted_boxes;
  const unsigned long long* total;  // the entries the boxes need, counted on the device
  uint32_t planned;                 // entries the arrays hold this build

  // The real entries among the planned ones (the rest is padding).
  CDB_HD uint32_t entries() const { return static_cast<uint32_t>(min_of(*total, (unsigned long long)planned)); }
};

}  // namespace cdb
