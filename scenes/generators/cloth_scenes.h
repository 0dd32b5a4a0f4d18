#pragma once
// The simulated cloth scenes: funnel, cloth-ball, flag, sphere. Each reads its parameters
// (see docs/design.md, Scenes) and rejects unknown ones.
#include <memory>

#include "cdbench/geometry/frame_source.h"
#include "scenes/generators/params.h"

namespace cdb::scene {

std::unique_ptr<FrameSource> make_funnel(Params& p);
std::unique_ptr<FrameSource> make_cloth_ball(Params& p);
std::unique_ptr<FrameSource> make_flag(Params& p);
std::unique_ptr<FrameSource> make_sphere_hit(Params& p);

}  // namespace cdb::scene
