#pragma once
// Registration of the uniform grid's boxes: each box in every cell of its level that its
// closed box overlaps, as (cell key, box) entries to be radix-sorted by key.
//
// The entry array is sized on the host before the frame's one read-back, from the last
// frame's count (uniform_grid.h): entries past that plan are counted, not written, and the
// host re-runs the frame with a larger plan. The unused tail of the plan is padded with a
// key above every real key, so after the sort the real entries come first.
#include <cstdint>

#include "baselines/grid/grid_arrays.h"
#include "baselines/grid/grid_geometry.h"

namespace cdb {

// Per box: its level (the finest that keeps it within kGridMaxCellsPerBox cells) and how
// many cells it covers there.
struct GridCountFn {
  GridArrays g;  // writes counts and level
  CDB_HD void operator()(uint32_t i) const {
    const GridLayout& p = *g.params;
    const vec4f a = g.lo[i], b = g.hi[i];
    uint32_t l = level_of_width(p, box_width(a, b));
    uint64_t cells = grid_range(p, l, a, b).cells();
    while (cells > kGridMaxCellsPerBox && l + 1 < p.levels)
      cells = grid_range(p, ++l, a, b).cells();
    g.counts[i] = static_cast<uint32_t>(cells);
    g.level[i] = l;
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
  GridArrays g;  // writes keys and boxes, at most planned of them
  CDB_HD void operator()(uint32_t i) const {
    const GridLayout& p = *g.params;
    const uint32_t l = g.level[i];
    uint32_t e = g.offsets[i];
    for_each_cell(grid_range(p, l, g.lo[i], g.hi[i]), [&](CellCoords cell) {
      if (e >= g.planned) return false;
      g.keys[e] = grid_key(p, l, cell);
      g.boxes[e++] = i;
      return true;
    });
  }
};

// The planned entries past the real total get the padding key (2^key_bits - 1, above
// every real key when the key bits suffice; when they do not, the frame is re-run).
struct GridPadFn {
  GridArrays g;
  uint64_t pad_key;
  CDB_HD void operator()(uint32_t e) const {
    if (e < *g.total) return;
    g.keys[e] = pad_key;
    g.boxes[e] = 0;
  }
};

// First sorted entry of each level (levels past the last, and the end, get the entry
// count): one thread per level, a binary search for the level's first key.
struct LevelBeginFn {
  GridArrays g;  // writes level_begin
  CDB_HD void operator()(uint32_t l) const {
    const uint32_t entries = g.entries();
    if (l >= g.params->levels) {
      g.level_begin[l] = entries;
      return;
    }
    g.level_begin[l] = lower_bound_key(g.sorted_keys, 0, entries, g.params->level[l].base);
  }
};

}  // namespace cdb
