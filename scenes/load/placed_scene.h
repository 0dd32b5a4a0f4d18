#pragma once
// A scene moved and scaled in double (--set placement.offset=1e7 placement.scale=1e-3, or
// the descriptor's "placement": {"offset", "scale"}): p -> scale * p + offset per vertex,
// so millimetre features far from the origin can be asked of any scene; the double
// positions keep them (docs/design.md "Box precision").
#include <array>
#include <memory>

#include <nlohmann/json.hpp>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

struct Placement {
  double scale = 1.0;
  std::array<double, 3> offset{0.0, 0.0, 0.0};
  bool identity() const { return scale == 1.0 && offset[0] == 0.0 && offset[1] == 0.0 && offset[2] == 0.0; }
};

// The keys "placement.scale" and "placement.offset" (a number for every axis, or [x, y, z])
// of `j`; throws naming `where` and the key on a non-finite, non-positive scale or a
// malformed offset. Keys it does not know are left to the caller.
Placement parse_placement(const nlohmann::json& j, const std::string& where);

std::unique_ptr<FrameSource> place_scene(std::unique_ptr<FrameSource> source, const Placement& placement);

}  // namespace cdb
