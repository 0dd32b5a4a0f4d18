#pragma once
// Built-in procedural scenes, deterministic from their parameters (seed included).
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenes/generators/generator_parameter.h"
#include "cdbench/geometry/frame_source.h"
#include "scenes/generators/scene_inputs.h"

namespace cdb {

// Known generators: soup, cloth-wave, crumple (kinematic); funnel, cloth-ball, flag, sphere
// (simulated cloth, see cloth_scenes.h); n-body (rigid bodies); flamenco and dragon (built on
// packaged files, see paper_scenes.h). Unknown parameters are an error that lists the known ones;
// out-of-range values and running out of memory are errors naming the parameters.
// `described`, when given, receives every parameter with its default, range and the value
// used. `inputs` opens the files flamenco and dragon read; without it they are an error.
std::unique_ptr<FrameSource> make_generator(const std::string& name, const nlohmann::json& params,
                                            std::vector<GeneratorParameter>* described = nullptr,
                                            const scene::SceneInputs* inputs = nullptr);
const std::vector<std::string>& generator_names();

}  // namespace cdb
