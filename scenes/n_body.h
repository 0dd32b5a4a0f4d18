#pragma once
// Paper's N-body: hundreds of balls and a few cones bouncing in a closed box (the box's
// walls are not part of the mesh). Rigid bodies only.
#include <memory>

#include "geometry/frame_source.h"
#include "params.h"

namespace cdb::scene {

std::unique_ptr<FrameSource> make_n_body(Params& p);

}  // namespace cdb::scene
