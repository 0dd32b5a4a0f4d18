#pragma once
// How a frame's double positions become the floats every pipeline runs on
// (--box-precision; docs/design.md "Box precision").
//
// fp32 and q16 round each coordinate to the nearest float. Far from the origin that loses
// the geometry: at 1e7 floats are 1.0 apart, so millimetre triangles collapse onto a few
// points (many extra pairs, never a missed one: see below).
//
// fp64 first subtracts, in double, an origin fixed at the first frame after a topology
// (the centre of that frame's bounds), then rounds to the nearest float: the floats then
// resolve the scene's extent, not its distance from the origin.
//
// Both are conservative without widening a box: x -> float(x - o) never decreases, so it
// keeps the order of any two coordinates, and a triangle box (min and max of its corners)
// and the overlap test (lo <= hi on every axis) are kept with it: every pair of the
// double geometry is a pair of the floats. A margin breaks this (lo - m <= hi + m is not
// kept when both sides round apart), which is why fp64 boxes with a margin first widen by
// one float spacing (geometry/mesh.h).
#include <vector>

#include "cdbench/core/vec.h"

namespace cdb {

class PositionRounding {
 public:
  explicit PositionRounding(bool rebase = false) : rebase_(rebase) {}
  // The next frame picks the origin again (a new topology, a new pass).
  void restart() { have_origin_ = false; }
  // `in` rounded as the precision says, into `out` (resized; no allocation once it fits).
  void round(const std::vector<vec3d>& in, std::vector<vec3f>& out);
  bool rebases() const { return rebase_; }
  // The origin subtracted before rounding ({0, 0, 0} without a rebase).
  vec3d origin() const { return origin_; }

 private:
  bool rebase_;
  bool have_origin_ = false;
  vec3d origin_{0, 0, 0};
};

// The centre of the positions' bounds ({0, 0, 0} for none).
vec3d bounds_centre(const std::vector<vec3d>& p);

}  // namespace cdb
