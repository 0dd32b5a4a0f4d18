#pragma once
// Pair tests of the uniform grid, each overlapping pair reported exactly once.
//
// The rule is the cell baselines' ownership rule (common/home_cell.h): a pair is reported
// only from its home cell, the one holding m, the minimum corner of the intersection of
// the two closed boxes. Every box is registered in the cell of m on its own level. So:
// - two boxes of one level meet in exactly one cell that passes the rule, where the
//   thread of the earlier sorted entry tests the later one (SameLevelPairsFn);
// - a box a on a finer level than b is tested by a's thread against the cells a's box
//   covers on b's level (at most 3 per axis: a is narrower than that level's cell); a
//   covers the cell of m there, b is registered in it, and the rule keeps the one test
//   that reports it (CoarserLevelPairsFn). b never looks at finer levels.
#include <cstdint>

#include "baselines/common/home_cell.h"
#include "baselines/common/staged_pairs.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/pair_sink.h"
#include "baselines/grid/grid_arrays.h"
#include "baselines/grid/grid_geometry.h"

namespace cdb {

// One thread per sorted entry: the later entries of its cell.
struct SameLevelPairsFn : StagedPairs {
  GridArrays g;
  CDB_HD void operator()(uint32_t k, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const uint32_t entries = g.entries();
    if (k >= entries) return;
    const uint64_t* keys = g.sorted_keys;
    const uint32_t* boxes = g.sorted_boxes;
    const uint64_t key = keys[k];
    const uint32_t l = g.level[boxes[k]];
    emit_later_in_cell(
        k, entries, boxes, g.lo, g.hi, [&](uint32_t t) { return keys[t] == key; }, [](uint32_t) { return true; },
        [&](const vec4f& alo, const vec4f& blo) {
          return grid_key(*g.params, l, home_cell(level_lattice(*g.params, l), alo, blo)) == key;
        },
        out);
  }
};

// One thread per box: the boxes of every coarser, non-empty level in the cells its box
// covers there. Scenes of one level return at once.
struct CoarserLevelPairsFn : StagedPairs {
  GridArrays g;
  CDB_HD void operator()(uint32_t a, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const GridLayout& p = *g.params;
    const uint64_t* keys = g.sorted_keys;
    const uint32_t* boxes = g.sorted_boxes;
    const vec4f alo = g.lo[a], ahi = g.hi[a];
    for (uint32_t l = g.level[a] + 1; l < p.levels; ++l) {
      const uint32_t begin = g.level_begin[l], end = g.level_begin[l + 1];
      if (begin == end) continue;
      const CellLattice<float> lattice = level_lattice(p, l);
      for_each_cell(cell_range(lattice, alo, ahi), [&](CellCoords cell) {
        const uint64_t key = grid_key(p, l, cell);
        for (uint32_t t = lower_bound_key(keys, begin, end, key); t < end && keys[t] == key; ++t) {
          const uint32_t b = boxes[t];
          const vec4f blo = g.lo[b], bhi = g.hi[b];
          if (overlaps(alo, ahi, blo, bhi) && grid_key(p, l, home_cell(lattice, alo, blo)) == key) out.emit(a, b);
        }
        return true;
      });
    }
  }
};

}  // namespace cdb
