#include "io/scene.h"

#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "generators.h"
#include "io/obj_sequence.h"

namespace cdb {
namespace {

Scene open_descriptor(const std::filesystem::path& file, const nlohmann::json& overrides) {
  std::ifstream in(file);
  if (!in) fail(file.string() + ": cannot open scene descriptor");
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(file.string() + ": malformed JSON: " + e.what());
  }
  if (!j.is_object()) fail(file.string() + ": a scene descriptor must be a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "description" && it.key() != "generator" && it.key() != "params" &&
        it.key() != "frames")
      fail(file.string() + ": /" + it.key() + ": unknown key (description, generator, params, frames)");
  Scene s;
  s.name = file.stem().string();
  if (j.contains("description")) {
    if (!j["description"].is_string()) fail(file.string() + ": /description: must be a string");
    s.description = j["description"].get<std::string>();
  }
  if (j.contains("generator") == j.contains("frames"))
    fail(file.string() + ": needs exactly one of /generator (procedural) or /frames (mesh directory)");
  if (j.contains("generator")) {
    if (!j["generator"].is_string()) fail(file.string() + ": /generator: must be a string");
    nlohmann::json params = j.contains("params") ? j["params"] : nlohmann::json::object();
    if (!params.is_object()) fail(file.string() + ": /params: must be an object");
    for (auto it = overrides.begin(); it != overrides.end(); ++it) params[it.key()] = it.value();
    try {
      s.source = make_generator(j["generator"].get<std::string>(), params);
    } catch (const Error& e) {
      fail(file.string() + ": " + e.what());
    }
  } else {
    if (j.contains("params")) fail(file.string() + ": /params: only valid with /generator");
    if (!overrides.empty()) fail(file.string() + ": parameters can only be set on a procedural scene");
    if (!j["frames"].is_string()) fail(file.string() + ": /frames: must be a string (a directory)");
    std::filesystem::path dir = j["frames"].get<std::string>();
    if (dir.is_relative()) dir = file.parent_path() / dir;
    s.source = open_mesh_sequence(dir);
  }
  if (s.description.empty()) s.description = s.source->describe();
  return s;
}

}  // namespace

std::filesystem::path default_scenes_dir() {
  if (const char* env = std::getenv("CDBENCH_SCENES")) return env;
  return CDB_SCENES_DIR;
}

std::vector<std::string> list_scenes(const std::filesystem::path& scenes_dir) {
  std::vector<std::string> names;
  if (std::filesystem::is_directory(scenes_dir))
    for (const auto& e : std::filesystem::directory_iterator(scenes_dir))
      if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

Scene open_scene(const std::string& spec, const std::filesystem::path& scenes_dir,
                 const nlohmann::json& overrides) {
  const std::filesystem::path p(spec);
  if (std::filesystem::is_directory(p)) {
    if (!overrides.empty()) fail(spec + ": parameters can only be set on a procedural scene");
    Scene s;
    s.name = p.filename().string();
    s.source = open_mesh_sequence(p);
    s.description = s.source->describe();
    return s;
  }
  if (p.extension() == ".json") return open_descriptor(p, overrides);
  const auto named = scenes_dir / (spec + ".json");
  if (std::filesystem::is_regular_file(named)) return open_descriptor(named, overrides);
  std::string known;
  for (const auto& n : list_scenes(scenes_dir)) known += (known.empty() ? "" : ", ") + n;
  fail("unknown scene '" + spec + "': not a directory of mesh frames, not a .json descriptor, and not in " +
       scenes_dir.string() + " (known: " + known + ")");
}

}  // namespace cdb
