#include "io/scene.h"

#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "generators.h"
#include "io/animated_mesh.h"
#include "io/frame_cache.h"
#include "io/obj_sequence.h"

namespace cdb {
namespace {

// A scene's frames with the objects and queries its descriptor declares.
class DeclaredQueries final : public FrameSource {
 public:
  DeclaredQueries(std::unique_ptr<FrameSource> inner, Topology topology)
      : inner_(std::move(inner)), topology_(std::move(topology)) {}
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return inner_->num_frames(); }
  void frame(uint32_t k, std::vector<vec3f>& out) const override { inner_->frame(k, out); }
  std::string describe() const override { return inner_->describe(); }

 private:
  std::unique_ptr<FrameSource> inner_;
  Topology topology_;
};

uint32_t object_index(const std::vector<SceneObject>& objects, const nlohmann::json& name,
                      const std::string& where) {
  if (!name.is_string()) fail(where + ": must be an object name (a string)");
  for (uint32_t o = 0; o < objects.size(); ++o)
    if (objects[o].name == name.get<std::string>()) return o;
  std::string known;
  for (const auto& ob : objects) known += (known.empty() ? "" : ", ") + ob.name;
  fail(where + ": unknown object '" + name.get<std::string>() + "' (objects: " +
       (known.empty() ? "none" : known) + ")");
}

// "objects": [{"name", "faces": [first, count], "rigid"}] replaces the generator's objects;
// "queries": {"self": [names], "inter": [[a, b], ...]} declares what to report.
std::unique_ptr<FrameSource> declare_queries(std::unique_ptr<FrameSource> source, const nlohmann::json& j,
                                             const std::string& file) {
  Topology topo = source->topology();
  if (j.contains("objects")) {
    const auto& objs = j["objects"];
    if (!objs.is_array()) fail(file + ": /objects: must be an array");
    topo.objects.clear();
    for (size_t k = 0; k < objs.size(); ++k) {
      const std::string at = file + ": /objects/" + std::to_string(k);
      const auto& o = objs[k];
      if (!o.is_object()) fail(at + ": must be an object");
      for (auto it = o.begin(); it != o.end(); ++it)
        if (it.key() != "name" && it.key() != "faces" && it.key() != "rigid")
          fail(at + "/" + it.key() + ": unknown key (name, faces, rigid)");
      if (!o.contains("name") || !o["name"].is_string()) fail(at + "/name: must be a string");
      if (!o.contains("faces") || !o["faces"].is_array() || o["faces"].size() != 2 ||
          !o["faces"][0].is_number_unsigned() || !o["faces"][1].is_number_unsigned())
        fail(at + "/faces: must be [first, count]");
      if (o.contains("rigid") && !o["rigid"].is_boolean()) fail(at + "/rigid: must be true or false");
      topo.objects.push_back({o["name"].get<std::string>(), o["faces"][0].get<uint32_t>(),
                              o["faces"][1].get<uint32_t>(), o.value("rigid", false)});
    }
  }
  if (j.contains("queries")) {
    const auto& q = j["queries"];
    const std::string at = file + ": /queries";
    if (!q.is_object()) fail(at + ": must be an object with self and/or inter");
    for (auto it = q.begin(); it != q.end(); ++it)
      if (it.key() != "self" && it.key() != "inter") fail(at + "/" + it.key() + ": unknown key (self, inter)");
    if (topo.objects.empty()) fail(at + ": the scene has no objects to query");
    topo.queries.declared = true;
    if (q.contains("self")) {
      if (!q["self"].is_array()) fail(at + "/self: must be an array of object names");
      for (size_t k = 0; k < q["self"].size(); ++k)
        topo.queries.self.push_back(object_index(topo.objects, q["self"][k], at + "/self/" + std::to_string(k)));
    }
    if (q.contains("inter")) {
      if (!q["inter"].is_array()) fail(at + "/inter: must be an array of [a, b] object-name pairs");
      for (size_t k = 0; k < q["inter"].size(); ++k) {
        const auto& p = q["inter"][k];
        const std::string pat = at + "/inter/" + std::to_string(k);
        if (!p.is_array() || p.size() != 2) fail(pat + ": must be [a, b]");
        topo.queries.inter.emplace_back(object_index(topo.objects, p[0], pat + "/0"),
                                        object_index(topo.objects, p[1], pat + "/1"));
      }
    }
  }
  try {
    if (topo.queries.declared) pair_filter_tables(topo.objects, topo.queries, topo.faces.size());
  } catch (const Error& e) {
    fail(file + ": " + e.what());
  }
  return std::make_unique<DeclaredQueries>(std::move(source), std::move(topo));
}

// Where the model files under /usr/share/assimp come from, for the error a user meets
// before installing them.
constexpr const char* kTestModelsDir = "/usr/share/assimp/models";

// "animation": {"file", "fps", "frames", "start", "clip"}: one animated file sampled at fps.
std::unique_ptr<FrameSource> open_animation(const nlohmann::json& a, const std::filesystem::path& descriptor) {
  const std::string at = descriptor.string() + ": /animation";
  if (!a.is_object()) fail(at + ": must be an object with file, fps, frames, start, clip");
  for (auto it = a.begin(); it != a.end(); ++it)
    if (it.key() != "file" && it.key() != "fps" && it.key() != "frames" && it.key() != "start" && it.key() != "clip")
      fail(at + "/" + it.key() + ": unknown key (file, fps, frames, start, clip)");
  AnimationOptions o;
  if (!a.contains("file") || !a["file"].is_string()) fail(at + "/file: must be a string (a model file)");
  o.file = a["file"].get<std::string>();
  if (o.file.is_relative()) o.file = descriptor.parent_path() / o.file;
  if (a.contains("fps")) {
    if (!a["fps"].is_number() || !(a["fps"].get<double>() > 0)) fail(at + "/fps: must be a positive number");
    o.fps = a["fps"].get<double>();
  }
  if (a.contains("frames")) {
    if (!a["frames"].is_number_unsigned() || a["frames"].get<uint64_t>() == 0 ||
        a["frames"].get<uint64_t>() > UINT32_MAX)
      fail(at + "/frames: must be a positive integer");
    o.frames = a["frames"].get<uint32_t>();
  }
  if (a.contains("start")) {
    if (!a["start"].is_number() || !(a["start"].get<double>() >= 0)) fail(at + "/start: must be a number >= 0 (seconds)");
    o.start = a["start"].get<double>();
  }
  if (a.contains("clip")) {
    if (a["clip"].is_string()) o.clip_name = a["clip"].get<std::string>();
    else if (a["clip"].is_number_unsigned()) o.clip = a["clip"].get<uint32_t>();
    else fail(at + "/clip: must be a clip index or name");
  }
  if (!std::filesystem::exists(o.file)) {
    std::string hint;
    if (o.file.string().rfind(kTestModelsDir, 0) == 0)
      hint = " (it ships with the Debian package assimp-testmodels: run scripts/install-deps.sh --scenes)";
    fail(at + "/file: " + o.file.string() + ": no such file" + hint);
  }
  try {
    return open_animated_mesh(o);
  } catch (const Error& e) {
    fail(at + ": " + e.what());
  }
}

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
        it.key() != "frames" && it.key() != "animation" && it.key() != "objects" && it.key() != "queries")
      fail(file.string() + ": /" + it.key() +
           ": unknown key (description, generator, params, frames, animation, objects, queries)");
  Scene s;
  s.name = file.stem().string();
  if (j.contains("description")) {
    if (!j["description"].is_string()) fail(file.string() + ": /description: must be a string");
    s.description = j["description"].get<std::string>();
  }
  if (int(j.contains("generator")) + int(j.contains("frames")) + int(j.contains("animation")) != 1)
    fail(file.string() +
         ": needs exactly one of /generator (procedural), /frames (mesh directory) or /animation (animated file)");
  if (j.contains("generator")) {
    if (!j["generator"].is_string()) fail(file.string() + ": /generator: must be a string");
    nlohmann::json params = j.contains("params") ? j["params"] : nlohmann::json::object();
    if (!params.is_object()) fail(file.string() + ": /params: must be an object");
    for (auto it = overrides.begin(); it != overrides.end(); ++it) params[it.key()] = it.value();
    try {
      const std::string generator = j["generator"].get<std::string>();
      s.source = cache_frames(make_generator(generator, params), generator + " " + params.dump(),
                              frame_cache_dir());
    } catch (const Error& e) {
      fail(file.string() + ": " + e.what());
    }
  } else {
    if (j.contains("params")) fail(file.string() + ": /params: only valid with /generator");
    if (!overrides.empty()) fail(file.string() + ": parameters can only be set on a procedural scene");
  }
  if (j.contains("animation")) {
    s.source = open_animation(j["animation"], file);
  } else if (j.contains("frames")) {
    if (!j["frames"].is_string()) fail(file.string() + ": /frames: must be a string (a directory)");
    std::filesystem::path dir = j["frames"].get<std::string>();
    if (dir.is_relative()) dir = file.parent_path() / dir;
    s.source = open_mesh_sequence(dir);
  }
  if (j.contains("objects") || j.contains("queries"))
    s.source = declare_queries(std::move(s.source), j, file.string());
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
    // "frames/" names the directory "frames", not "".
    const std::filesystem::path named = p.has_filename() ? p : p.parent_path();
    s.name = named.filename().string();
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
