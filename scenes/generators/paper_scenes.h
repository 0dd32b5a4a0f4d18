#pragma once
// The paper's Flamenco and Dragon benchmarks (Wang et al. 2018, Table 1 and Figure 9),
// built on files that Debian packages ship: a skinned character from assimp-testmodels
// and a scan from libcgal-demo, opened through `inputs` (scene_inputs.h).
#include <memory>

#include "cdbench/geometry/frame_source.h"
#include "scenes/generators/params.h"
#include "scenes/generators/scene_inputs.h"

namespace cdb::scene {

std::unique_ptr<FrameSource> make_flamenco(Params& p, const SceneInputs& inputs);
std::unique_ptr<FrameSource> make_dragon(Params& p, const SceneInputs& inputs);

}  // namespace cdb::scene
