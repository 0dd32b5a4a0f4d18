#include "cdbench/geometry/position_rounding.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "cdbench/core/error.h"

namespace cdb {

vec3d bounds_centre(const std::vector<vec3d>& p) {
  if (p.empty()) return {0, 0, 0};
  vec3d lo = p[0], hi = p[0];
  for (const vec3d& v : p) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
  // Halves first: lo + hi can overflow where the positions do not.
  return {lo.x / 2 + hi.x / 2, lo.y / 2 + hi.y / 2, lo.z / 2 + hi.z / 2};
}

namespace {

// A coordinate beyond +-FLT_MAX rounds to infinity, which no box can hold.
void check_float_range(const std::vector<vec3d>& in, const std::vector<vec3f>& out, bool rebased) {
  for (size_t v = 0; v < out.size(); ++v)
    if (!std::isfinite(out[v].x) || !std::isfinite(out[v].y) || !std::isfinite(out[v].z))
      fail("vertex " + std::to_string(v) + ": position (" + std::to_string(in[v].x) + ", " +
           std::to_string(in[v].y) + ", " + std::to_string(in[v].z) + ") is beyond float range" +
           (rebased ? " even from the frame's origin: the scene is wider than float holds"
                    : "; --box-precision fp64 rebases the scene before rounding"));
}

}  // namespace

void PositionRounding::round(const std::vector<vec3d>& in, std::vector<vec3f>& out) {
  if (rebase_ && !have_origin_) {
    origin_ = bounds_centre(in);
    have_origin_ = true;
  }
  // Without a rebase the origin is {0, 0, 0}, and x - 0 is x exactly.
  out.resize(in.size());
  const vec3d o = origin_;
  for (size_t v = 0; v < in.size(); ++v)
    out[v] = {static_cast<float>(in[v].x - o.x), static_cast<float>(in[v].y - o.y),
              static_cast<float>(in[v].z - o.z)};
  check_float_range(in, out, rebase_);
}

}  // namespace cdb
