#pragma once
// Paper's N-body: hundreds of balls and a few cones bouncing in a closed box (the box's
// walls are not part of the mesh). Rigid bodies only. Gravity, restitution, the box's fill
// and the contact sweeps per substep are parameters: the `spheres` scene drops its balls
// from rest to bounce and pile up on the floor.
#include <memory>

#include "cdbench/geometry/frame_source.h"
#include "scenes/generators/params.h"

namespace cdb::scene {

std::unique_ptr<FrameSource> make_n_body(Params& p);

}  // namespace cdb::scene
