#pragma once
// Whether float boxes can hold a scene (docs/design.md "Box precision"): float's spacing at
// the scene's largest coordinate against its smallest features. When the spacing exceeds
// kFeatureFraction of the median edge, rounding moves vertices by a visible part of a
// triangle: boxes grow and merge, so pairs multiply (never lost: position_rounding.h).
#include <string>
#include <vector>

#include "cdbench/core/vec.h"
#include "cdbench/geometry/frame_source.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

inline constexpr double kFeatureFraction = 1e-3;

struct FloatSpacing {
  double largest = 0.0;      // largest |coordinate| after subtracting the origin
  double spacing = 0.0;      // float's spacing there
  double median_edge = 0.0;  // over every triangle edge, in double
  bool too_coarse() const { return median_edge > 0.0 && spacing > kFeatureFraction * median_edge; }
};

// `origin`: what the pipeline subtracts before rounding (fp64's, else {0, 0, 0}).
FloatSpacing float_spacing(const Topology& topology, const std::vector<vec3d>& positions, vec3d origin);

// The warning for too coarse a spacing, naming the remedy (empty when the spacing is fine).
// `rebased`: the positions are already rebased (fp64), so no precision choice helps.
std::string float_spacing_warning(const FloatSpacing& s, bool rebased);
// The same for frame k of a source, rounded as fp64 (`rebase`) or fp32 would round it.
std::string float_spacing_warning(const FrameSource& source, uint32_t k, bool rebase);

}  // namespace cdb
