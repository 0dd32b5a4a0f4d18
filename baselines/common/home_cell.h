#pragma once
// The ownership rule of the cell baselines (grid and hash; the standard one for grids, as
// in OTG and kDet): an overlapping pair is reported only from its home cell, the cell of
// m, the minimum corner of the intersection of the two closed boxes. m lies in both
// boxes, so, the cell coordinate being monotone (cell_coord.h), both boxes are registered
// in m's cell and the pair is found there; every other cell the two share skips it. Boxes
// that only touch (m on a cell face) and rounding need no special case: m's cell comes
// from the same function that registered both boxes.
#include "common/cell_range.h"
#include "core/hd.h"
#include "core/vec.h"

namespace cdb {

template <class Real>
CDB_HD_INLINE CellCoords home_cell(const CellLattice<Real>& g, const vec4<Real>& alo,
                                   const vec4<Real>& blo) {
  return cell_of(g, vec4<Real>{max_of(alo.x, blo.x), max_of(alo.y, blo.y), max_of(alo.z, blo.z),
                               Real(0)});
}

}  // namespace cdb
