#pragma once
// A square sheet squeezed towards its middle and churned onto itself: its folds lie
// over one another more and more, and parts of the sheet far apart at frame 0 end up in
// contact, so a hierarchy built on frame 0 goes stale (see crumple.cpp).
#include <memory>

#include "cdbench/geometry/frame_source.h"
#include "scenes/generators/params.h"

namespace cdb::scene {

std::unique_ptr<FrameSource> make_crumple(Params& p);

}  // namespace cdb::scene
