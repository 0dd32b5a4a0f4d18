#pragma once
// Whether --box-margin keeps a frame's boxes within float range. Each box side moves out
// by the margin, rounded outward (geometry/mesh.h face_box): a side within the margin of
// +-FLT_MAX becomes +-inf, a box no float holds, and the margin is then more than the
// scene's floats can carry. The check runs on the floats a pipeline is given, after
// --box-precision's rounding (fp64 rebases first, and with a margin widens each side by
// one float spacing before adding it: `widen`).
#include <vector>

#include "cdbench/core/vec.h"

namespace cdb {

// Throws UsageError naming --box-margin, the vertex and its coordinate when the margin
// takes a box side at that vertex past float range.
void check_margin_in_float_range(const std::vector<vec3f>& vertices, float margin, bool widen);

}  // namespace cdb
