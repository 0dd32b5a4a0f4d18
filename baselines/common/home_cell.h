#pragma once
// The ownership rule of the cell baselines (grid and hash; the standard one for grids, as
// in OTG and kDet): an overlapping pair is reported only from its home cell, the cell of
// m, the minimum corner of the intersection of the two closed boxes. m lies in both
// boxes, so, the cell coordinate being monotone (cell_coord.h), both boxes are registered
// in m's cell and the pair is found there; every other cell the two share skips it. Boxes
// that only touch (m on a cell face) and rounding need no special case: m's cell comes
// from the same function that registered both boxes.
#include "baselines/common/cell_range.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/core/vec.h"

namespace cdb {

template <class Real>
CDB_HD_INLINE CellCoords home_cell(const CellLattice<Real>& g, const vec4<Real>& alo,
                                   const vec4<Real>& blo) {
  return cell_of(g, vec4<Real>{max_of(alo.x, blo.x), max_of(alo.y, blo.y), max_of(alo.z, blo.z),
                               Real(0)});
}

// The pair tests of sorted entry k of a cell's run, as both cell baselines make them: k's box
// against the box of every later entry t of the run (while same_run(t)) that lies in k's
// cell (in_cell(t)) and overlaps it, reported where is_home(a's lo, b's lo) says the pair's
// home cell is k's.
template <class SameRun, class InCell, class IsHome>
CDB_HD_INLINE void emit_later_in_cell(uint32_t k, uint32_t entries, const uint32_t* boxes, const vec4f* lo,
                                      const vec4f* hi, SameRun same_run, InCell in_cell, IsHome is_home,
                                      const PairSink& out) {
  const uint32_t a = boxes[k];
  const vec4f alo = lo[a], ahi = hi[a];
  for (uint32_t t = k + 1; t < entries && same_run(t); ++t) {
    if (!in_cell(t)) continue;
    const uint32_t b = boxes[t];
    const vec4f blo = lo[b], bhi = hi[b];
    if (overlaps(alo, ahi, blo, bhi) && is_home(alo, blo)) out.emit(a, b);
  }
}

}  // namespace cdb
