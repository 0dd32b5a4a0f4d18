#pragma once
// Registration of the uniform grid's boxes: each box in every cell of its level that its
// closed box overlaps, as (cell key, box) entries to be radix-sorted by key.
//
// The entry array is sized on the host before the frame's one read-back, from the last
// frame's count (uniform_grid.h): entries past that plan are counted, not written, and the
// host re-runs the frame with a larger plan. The unused tail of the plan is padded with a
// key above every real key, so after the sort the real entries come first.
#include <cstdint>

#include "baselines/grid/grid_geometry.h"

namespace cdb {

// Per box: its level (the finest that keeps it within kGridMaxCellsPerBox cells) and how
// many cells it covers there.
struct GridCountFn {
  const vec4f* lo;
  const vec4f* hi;
  const GridLayout* params;
  uint32_t* counts;
  uint32_t* level;
  CDB_HD void operator()(uint32_t i) const {
    const GridLayout& p = *params;
    const vec4f a = lo[i], b = hi[i];
    uint32_t l = level_of_width(p, box_width(a, b));
    uint64_t cells = grid_range(p, l, a, b).cells();
    while (cells > kGridMaxCellsPerBox && l + 1 < p.levels)
      cells = grid_range(p, ++l, a, b).cells();
    counts[i] = static_cast<uint32_t>(cells);
    level[i] = l;
  }
};

// The entry total, in 64 bits: the 32-bit offsets of the scan are valid only when it fits.
struct EntryTotalFn {
  const uint32_t* counts;
  CDB_HD unsigned long long operator()(uint32_t i) const { return counts[i]; }
};

struct SumOp {
  CDB_HD unsigned long long operator()(unsigned long long a, unsigned long long b) const {
    return a + b;
  }
};

struct GridFillFn {
  const vec4f* lo;
  const vec4f* hi;
  const GridLayout* params;
  const uint32_t* level;
  const uint32_t* offsets;
  uint32_t planned;  // entries the arrays hold this frame
  uint64_t* keys;
  uint32_t* boxes;
  CDB_HD void operator()(uint32_t i) const {
    const GridLayout& p = *params;
    const uint32_t l = level[i];
    uint32_t e = offsets[i];
    for_each_cell(grid_range(p, l, lo[i], hi[i]), [&](CellCoords cell) {
      if (e >= planned) return false;
      keys[e] = grid_key(p, l, cell);
      boxes[e++] = i;
      return true;
    });
  }
};

// The planned entries past the real total get the padding key (2^key_bits - 1, above
// every real key when the key bits suffice; when they do not, the frame is re-run).
struct GridPadFn {
  const unsigned long long* total;
  uint64_t pad_key;
  uint64_t* keys;
  uint32_t* boxes;
  CDB_HD void operator()(uint32_t e) const {
    if (e < *total) return;
    keys[e] = pad_key;
    boxes[e] = 0;
  }
};

// First sorted entry of each level (levels past the last, and the end, get the entry
// count): one thread per level, a binary search for the level's first key.
struct LevelBeginFn {
  const uint64_t* sorted_keys;
  const unsigned long long* total;
  uint32_t planned;
  const GridLayout* params;
  uint32_t* begin;
  CDB_HD void operator()(uint32_t l) const {
    const uint32_t entries = static_cast<uint32_t>(min_of(*total, (unsigned long long)planned));
    if (l >= params->levels) {
      begin[l] = entries;
      return;
    }
    begin[l] = lower_bound_key(sorted_keys, 0, entries, params->level[l].base);
  }
};

}  // namespace cdb
