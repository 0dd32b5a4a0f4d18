#pragma once
// Cells of points and boxes on one lattice of cubic cells: the hash's grid, or one level
// of the uniform grid. Every coordinate comes from cell_coord (cell_coord.h), so a box's
// range holds the cell of every point of the box.
#include <cstdint>

#include "baselines/common/cell_coord.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

// Cells of width 1 / inv_cell from `origin` on each axis (a view, passed by value).
template <class Real>
struct CellLattice {
  Real origin[3];
  Real inv_cell;
};

struct CellCoords {
  uint32_t x, y, z;
};

// The cells from lo to hi on each axis, both included.
struct CellRange {
  CellCoords lo, hi;
  CDB_HD_INLINE uint64_t cells() const {
    return (uint64_t(hi.x - lo.x) + 1) * (uint64_t(hi.y - lo.y) + 1) * (uint64_t(hi.z - lo.z) + 1);
  }
};

template <class Real>
CDB_HD_INLINE CellCoords cell_of(const CellLattice<Real>& g, const vec4<Real>& p) {
  return {cell_coord(p.x, g.origin[0], g.inv_cell), cell_coord(p.y, g.origin[1], g.inv_cell),
          cell_coord(p.z, g.origin[2], g.inv_cell)};
}

// Calls f(cell) for every cell of r, x fastest and z slowest (the order a box's entries are
// written in), until f returns false.
template <class F>
CDB_HD_INLINE void for_each_cell(const CellRange& r, F&& f) {
  for (uint32_t z = r.lo.z; z <= r.hi.z; ++z)
    for (uint32_t y = r.lo.y; y <= r.hi.y; ++y)
      for (uint32_t x = r.lo.x; x <= r.hi.x; ++x)
        if (!f(CellCoords{x, y, z})) return;
}

template <class Real>
CDB_HD_INLINE CellRange cell_range(const CellLattice<Real>& g, const vec4<Real>& lo,
                                   const vec4<Real>& hi) {
  return {cell_of(g, lo), cell_of(g, hi)};
}

}  // namespace cdb
