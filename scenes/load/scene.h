#pragma once
// Resolves what --scene names: a directory of mesh frames (io/obj_sequence.h) or of box
// frames (io/box_stream.h), a scene descriptor (.json), or the name of a descriptor in the
// scenes directory.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenes/generators/generator_parameter.h"
#include "cdbench/geometry/frame_source.h"

namespace cdb {

struct Scene {
  std::string name;
  std::string description;
  // The generator parameters `--set` overrode (an object, empty when none): part of the
  // scene's identity in results (io/scene_label.h).
  nlohmann::json overrides = nlohmann::json::object();
  // A procedural scene's generator parameters: defaults, ranges and the values used.
  std::vector<GeneratorParameter> parameters;
  std::unique_ptr<FrameSource> source;
};

// `overrides` (a JSON object) replaces or adds generator parameters of a procedural scene
// (an error for a mesh sequence); its keys placement.scale and placement.offset move any
// scene (io/placed_scene.h).
Scene open_scene(const std::string& spec, const std::filesystem::path& scenes_dir,
                 const nlohmann::json& overrides = nlohmann::json::object());

// Default scenes directory: $CDBENCH_SCENES, else the source tree's scenes/.
std::filesystem::path default_scenes_dir();

std::vector<std::string> list_scenes(const std::filesystem::path& scenes_dir);

}  // namespace cdb
