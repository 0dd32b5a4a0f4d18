#include "scenes/generators/params.h"
#include "scenes/load/scene.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "scenes/generators/generators.h"
#include "scenes/load/animated_mesh.h"
#include "scenes/load/archive_cache.h"
#include "scenes/load/box_stream.h"
#include "scenes/load/composed_scene.h"
#include "scenes/load/descriptor_object.h"
#include "scenes/load/frame_cache.h"
#include "scenes/load/input_files.h"
#include "scenes/load/keyframe_mesh.h"
#include "scenes/load/obj_sequence.h"
#include "scenes/load/placed_scene.h"
#include "scenes/load/rigid_mesh.h"
#include "scenes/load/scene_label.h"
#include "scenes/generators/scene_inputs.h"

namespace cdb {
namespace {

// A scene's frames with the objects and queries its descriptor declares.
class DeclaredQueries final : public FrameSource {
 public:
  DeclaredQueries(std::unique_ptr<FrameSource> inner, Topology topology)
      : inner_(std::move(inner)), topology_(std::move(topology)) {}
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return inner_->num_frames(); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override { inner_->positions(k, out); }
  std::string describe() const override { return inner_->describe(); }

 private:
  std::unique_ptr<FrameSource> inner_;
  Topology topology_;
};

// The files generators build on (scenes/generators/scene_inputs.h), opened as the descriptors' own
// keys open them; relative paths are the descriptor's.
class LoaderInputs final : public scene::SceneInputs {
 public:
  explicit LoaderInputs(std::filesystem::path dir) : dir_(std::move(dir)) {}
  // Each file opened so far, with its size and modification time.
  const std::string& identity() const { return identity_; }
  scene::InputMesh mesh(const std::string& file, const std::string& member) const override {
    std::filesystem::path path = existing(file);
    if (!member.empty()) path = extract_from_archive(path, member);
    StaticMesh m = load_static_mesh(path, 1.0, false);
    return {std::move(m.positions), std::move(m.faces)};
  }
  scene::InputAnimation animation(const std::string& file) const override {
    AnimationOptions o;
    o.file = existing(file);
    std::shared_ptr<const AnimatedClip> clip = open_animated_clip(o);
    return {clip->topology(), clip->clip_seconds(),
            [clip](double seconds, std::vector<vec3f>& out) { clip->positions_at(seconds, out); }};
  }

 private:
  std::filesystem::path existing(const std::string& file) const {
    std::filesystem::path path = file;
    if (path.is_relative()) path = dir_ / path;
    if (!std::filesystem::exists(path)) fail(path.string() + ": no such file" + package_hint(path));
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    const auto time = std::filesystem::last_write_time(path, ec).time_since_epoch().count();
    identity_ += " " + path.string() + ":" + std::to_string(size) + ":" + std::to_string(time);
    return path;
  }
  std::filesystem::path dir_;
  mutable std::string identity_;
};

// Runs `open`, prefixing its error with the descriptor path of what it opens or checks.
template <class Open>
auto opened_at(const std::string& where, Open open) {
  try {
    return open();
  } catch (const UsageError& e) {
    fail_usage(where + ": " + e.what());
  } catch (const Error& e) {
    fail(where + ": " + e.what());
  }
}

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
      const DescriptorObject object(o, at, {"name", "faces", "rigid"});
      std::string name = object.text("name");
      if (!o.contains("faces") || !o["faces"].is_array() || o["faces"].size() != 2 ||
          !o["faces"][0].is_number_unsigned() || !o["faces"][1].is_number_unsigned())
        fail(at + "/faces: must be [first, count]");
      // Face indices are 32-bit: a larger number would wrap into another face.
      for (int k = 0; k < 2; ++k)
        if (o["faces"][k].get<uint64_t>() > UINT32_MAX)
          fail(at + "/faces/" + std::to_string(k) + ": " + std::to_string(o["faces"][k].get<uint64_t>()) +
               " is beyond the largest face index, " + std::to_string(UINT32_MAX));
      topo.objects.push_back({std::move(name), o["faces"][0].get<uint32_t>(), o["faces"][1].get<uint32_t>(),
                              object.flag("rigid", false)});
    }
  }
  if (j.contains("queries")) {
    const auto& q = j["queries"];
    const std::string at = file + ": /queries";
    if (!q.is_object()) fail(at + ": must be an object with self and/or inter");
    const DescriptorObject queries(q, at, {"self", "inter"});
    if (topo.objects.empty()) fail(at + ": the scene has no objects to query");
    topo.queries.declared = true;
    if (queries.has("self")) {
      if (!q["self"].is_array()) fail(at + "/self: must be an array of object names");
      for (size_t k = 0; k < q["self"].size(); ++k)
        topo.queries.self.push_back(object_index(topo.objects, q["self"][k], at + "/self/" + std::to_string(k)));
    }
    if (queries.has("inter")) {
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
  if (topo.queries.declared)
    opened_at(file, [&] { pair_filter_tables(topo.objects, topo.queries, topo.faces.size()); });
  return std::make_unique<DeclaredQueries>(std::move(source), std::move(topo));
}

// "animation": {"file", "fps", "frames", "start", "clip"}: one animated file sampled at fps.
AnimationOptions animation_options(const DescriptorObject& a, const std::filesystem::path& descriptor) {
  AnimationOptions o;
  o.file = a.existing_file("file", descriptor.parent_path());
  o.fps = a.positive("fps", o.fps);
  o.frames = a.count("frames", 0, 1, UINT32_MAX);
  if (a.has("start")) {
    if (!a.raw("start").is_number() || !(a.raw("start").get<double>() >= 0))
      fail(a.at("start") + ": must be a number >= 0 (seconds)");
    o.start = a.raw("start").get<double>();
  }
  if (a.has("clip")) {
    if (a.raw("clip").is_string()) o.clip_name = a.raw("clip").get<std::string>();
    else if (a.raw("clip").is_number_unsigned()) o.clip = a.raw("clip").get<uint32_t>();
    else fail(a.at("clip") + ": must be a clip index or name");
  }
  return o;
}

// "keyframes": {"file", "first", "frames", "subframes"}: a per-vertex keyframe file (MD2, MD3, ...).
std::unique_ptr<FrameSource> open_keyframes(const DescriptorObject& k, const std::filesystem::path& descriptor) {
  KeyframeOptions o;
  o.file = k.existing_file("file", descriptor.parent_path());
  o.first = k.count("first", 0, 0, UINT32_MAX);
  o.frames = k.count("frames", 0, 1, UINT32_MAX);
  o.subframes = k.count("subframes", 1, 1, 1000);
  return opened_at(k.where(), [&] { return open_keyframe_mesh(o); });
}

// "crowd": {"animation", "count", "columns", "spacing", "phase_step", "up", "frames", "objects"}.
std::unique_ptr<FrameSource> open_crowd(const DescriptorObject& c, const std::filesystem::path& descriptor,
                                        const std::string& name) {
  CrowdOptions o;
  if (!c.has("animation")) fail(c.at("animation") + ": required (the character's animated file)");
  // Each instance loops the clip, so the crowd's own "frames" counts the frames.
  o.animation = animation_options(c.object("animation", {"file", "fps", "start", "clip"}), descriptor);
  o.count = c.count("count", o.count, 1, 1u << 20);
  o.columns = c.count("columns", 0, 1, 1u << 20);
  o.spacing = c.positive("spacing", o.spacing);
  o.phase_step = c.number("phase_step", o.phase_step);
  if (c.has("phase_step") && o.phase_step < 0) fail(c.at("phase_step") + ": must be a number >= 0 (seconds)");
  o.frames = c.count("frames", 0, 1, UINT32_MAX);
  if (c.has("up")) {
    const std::string up = c.text("up");
    if (up != "x" && up != "y" && up != "z") fail(c.at("up") + ": must be \"x\", \"y\" or \"z\"");
    o.up_axis = up[0] - 'x';
  }
  if (c.has("objects")) {
    const std::string objects = c.text("objects");
    if (objects != "instances" && objects != "crowd") fail(c.at("objects") + ": must be \"instances\" or \"crowd\"");
    o.instance_objects = objects == "instances";
  }
  o.name = name;
  return opened_at(c.where(), [&] { return cdb::open_crowd(o); });
}

// An existing directory of frames: box frames (io/box_stream.h) or mesh frames
// (io/obj_sequence.h), told apart by the files' extensions; a directory of both is refused
// rather than read as either, which would silently drop the other's files.
std::unique_ptr<FrameSource> open_frame_directory(const std::filesystem::path& dir) {
  const auto box_files = frame_files(dir, is_box_frame_file);
  const auto mesh_files = frame_files(dir, [](const std::filesystem::path& p) { return lower_extension(p) == ".obj"; });
  const std::filesystem::path box_file = box_files.empty() ? "" : box_files.back();
  const std::filesystem::path mesh_file = mesh_files.empty() ? "" : mesh_files.back();
  if (!box_file.empty() && !mesh_file.empty())
    fail(dir.string() + ": mixes box frames (" + box_file.filename().string() + ") and mesh frames (" +
         mesh_file.filename().string() + "): a frame directory holds one kind");
  return box_file.empty() ? open_mesh_sequence(dir) : open_box_stream(dir);
}

// "frames": DIR (box or mesh frames) or "boxes": DIR (box frames only), relative to the
// descriptor's directory.
std::unique_ptr<FrameSource> open_directory_key(const DescriptorObject& o, const char* key,
                                                const std::filesystem::path& descriptor) {
  if (!o.raw(key).is_string()) fail(o.at(key) + ": must be a string (a directory)");
  std::filesystem::path dir = o.raw(key).get<std::string>();
  if (dir.is_relative()) dir = descriptor.parent_path() / dir;
  if (!std::filesystem::is_directory(dir)) fail(o.at(key) + ": " + dir.string() + " is not a directory");
  return opened_at(o.at(key), [&] {
    return std::string(key) == "boxes" ? open_box_stream(dir) : open_frame_directory(dir);
  });
}

// The source `o` names by its one key among generator (with params), animation,
// keyframes, crowd, frames and boxes; `name` is the scene's or the part's and `where` names
// it in a generator's errors. `overrides` (--set) replace a generator's parameters or a
// crowd's keys. At the top level (`parameters` given) a generator's parameters are kept
// and its frames cached on disk.
std::unique_ptr<FrameSource> open_source(const DescriptorObject& o, const std::filesystem::path& descriptor,
                                         const std::string& name, const std::string& where,
                                         const nlohmann::json& overrides = nlohmann::json::object(),
                                         std::vector<GeneratorParameter>* parameters = nullptr) {
  if (o.has("generator")) {
    const std::string generator = o.text("generator");
    nlohmann::json params = o.has("params") ? o.raw("params") : nlohmann::json::object();
    if (!params.is_object()) fail(o.at("params") + ": must be an object");
    params.update(overrides);
    const LoaderInputs inputs(descriptor.parent_path());
    return opened_at(where, [&] {
      std::unique_ptr<FrameSource> made;
      try {
        made = make_generator(generator, params, parameters, &inputs);
      } catch (const scene::ParameterError& e) {
        // A value --set gave is a mistake in the call; one of the descriptor's is its data.
        if (overrides.contains(e.key)) fail_usage(std::string("--set ") + e.key + "=" + overrides[e.key].dump() + ": " + e.what());
        throw;
      }
      if (!parameters) return made;
      // The files it read are part of what it made: another package version is another key.
      return cache_frames(std::move(made), generator + " " + params.dump() + inputs.identity(), frame_cache_dir());
    });
  }
  if (o.has("animation")) {
    const AnimationOptions a =
        animation_options(o.object("animation", {"file", "fps", "frames", "start", "clip"}), descriptor);
    return opened_at(o.at("animation"), [&] { return open_animated_clip(a); });
  }
  if (o.has("keyframes"))
    return open_keyframes(o.object("keyframes", {"file", "first", "frames", "subframes"}), descriptor);
  if (o.has("crowd")) {
    nlohmann::json crowd = o.raw("crowd");
    if (crowd.is_object()) crowd.update(overrides);
    const DescriptorObject c(crowd, o.at("crowd"),
                             {"animation", "count", "columns", "spacing", "phase_step", "up", "frames", "objects"});
    return open_crowd(c, descriptor, name);
  }
  return open_directory_key(o, o.has("frames") ? "frames" : "boxes", descriptor);
}

scene::dvec3 dvec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// "motion": parametric {"fps", "position", "velocity", "axis", "angle", "angular_velocity",
// "pivot"} or keyed {"pivot", "keys": [{"frame", "position", "axis", "angle"}, ...]}.
RigidMotion rigid_motion(const DescriptorObject& m) {
  RigidMotion r;
  r.pivot = dvec(m.vec3("pivot", {0, 0, 0}));
  if (m.has("keys")) {
    for (const char* parametric : {"fps", "position", "velocity", "axis", "angle", "angular_velocity"})
      if (m.has(parametric)) fail(m.at(parametric) + ": not with keys (each key gives position, axis and angle)");
    const auto& keys = m.raw("keys");
    if (!keys.is_array() || keys.empty()) fail(m.at("keys") + ": must be a non-empty array of keys");
    for (size_t i = 0; i < keys.size(); ++i) {
      const DescriptorObject k(keys[i], m.at("keys") + "/" + std::to_string(i), {"frame", "position", "axis", "angle"});
      if (!k.has("frame")) fail(k.at("frame") + ": required");
      RigidKey key;
      key.frame = k.number("frame", 0);
      if (key.frame < 0 || (!r.keys.empty() && key.frame <= r.keys.back().frame))
        fail(k.at("frame") + ": must be >= 0 and after the previous key's");
      key.position = dvec(k.vec3("position", {0, 0, 0}));
      key.axis = dvec(k.vec3("axis", {0, 1, 0}));
      if (!(scene::length(key.axis) > 0)) fail(k.at("axis") + ": must not be zero");
      key.angle = k.number("angle", 0);
      r.keys.push_back(key);
    }
    return r;
  }
  r.fps = m.positive("fps", r.fps);
  r.position = dvec(m.vec3("position", {0, 0, 0}));
  r.velocity = dvec(m.vec3("velocity", {0, 0, 0}));
  r.axis = dvec(m.vec3("axis", {0, 1, 0}));
  if (!(scene::length(r.axis) > 0)) fail(m.at("axis") + ": must not be zero");
  r.angle = m.number("angle", 0);
  r.angular_velocity = m.number("angular_velocity", 0);
  return r;
}

// "mesh": {"file"} or {"archive", "member"}, with "scale" and "center".
StaticMesh static_mesh(const DescriptorObject& m, const std::filesystem::path& descriptor, std::string& origin) {
  std::filesystem::path file;
  if (m.has("file") == m.has("archive")) fail(m.where() + ": needs exactly one of file or archive (with member)");
  if (m.has("file")) {
    if (m.has("member")) fail(m.at("member") + ": only with archive");
    file = m.existing_file("file", descriptor.parent_path());
    origin = file.string();
  } else {
    const std::filesystem::path archive = m.existing_file("archive", descriptor.parent_path());
    const std::string member = m.text("member");
    file = opened_at(m.where(), [&] { return extract_from_archive(archive, member); });
    origin = archive.string() + ":" + member;
  }
  const double scale = m.positive("scale", 1.0);
  const bool center = m.flag("center", false);
  return opened_at(m.where(), [&] { return load_static_mesh(file, scale, center); });
}

// "parts": [{"name", one of generator (+ params), animation, keyframes, crowd, frames, boxes,
// mesh (+ motion)}] with "frame_count".
std::unique_ptr<FrameSource> open_parts(const DescriptorObject& root, const std::filesystem::path& descriptor) {
  const auto& parts = root.raw("parts");
  if (!parts.is_array() || parts.empty()) fail(root.at("parts") + ": must be a non-empty array of parts");
  struct Pending {
    std::string name, where;
    std::unique_ptr<FrameSource> source;  // null for a rigid mesh until the frame count is known
    StaticMesh mesh;
    RigidMotion motion;
    std::string origin;
  };
  std::vector<Pending> pending;
  std::set<std::string> names;
  for (size_t i = 0; i < parts.size(); ++i) {
    const DescriptorObject p(parts[i], root.at("parts") + "/" + std::to_string(i),
                             {"name", "generator", "params", "animation", "keyframes", "crowd", "frames", "boxes",
                              "mesh", "motion"});
    Pending part;
    part.where = p.where();
    part.name = p.text("name");
    if (!names.insert(part.name).second) fail(p.at("name") + ": '" + part.name + "' names an earlier part too");
    int kinds = 0;
    for (const char* kind : {"generator", "animation", "keyframes", "crowd", "frames", "boxes", "mesh"})
      kinds += p.has(kind);
    if (kinds != 1)
      fail(p.where() + ": needs exactly one of generator, animation, keyframes, crowd, frames, boxes, mesh");
    if (p.has("params") && !p.has("generator")) fail(p.at("params") + ": only with generator");
    if (p.has("motion") && !p.has("mesh")) fail(p.at("motion") + ": only with mesh");
    if (!p.has("mesh")) {
      part.source = open_source(p, descriptor, part.name, p.where());
    } else {
      part.mesh = static_mesh(p.object("mesh", {"file", "archive", "member", "scale", "center"}), descriptor,
                              part.origin);
      if (p.has("motion"))
        part.motion = rigid_motion(p.object("motion", {"fps", "position", "velocity", "axis", "angle",
                                                       "angular_velocity", "pivot", "keys"}));
    }
    pending.push_back(std::move(part));
  }
  uint32_t frames = root.count("frame_count", 0, 1, UINT32_MAX);
  if (!frames) {
    std::string counts;
    bool differ = false;
    for (const Pending& p : pending)
      if (p.source) {
        counts += (counts.empty() ? "" : ", ") + p.name + " " + std::to_string(p.source->num_frames());
        differ = differ || (frames && p.source->num_frames() != frames);
        frames = p.source->num_frames();
      }
    if (differ) fail(root.at("frame_count") + ": required when the parts' frame counts differ (" + counts + ")");
    if (!frames) fail(root.at("frame_count") + ": required when every part is a rigid mesh");
  }
  std::vector<ScenePart> scene_parts;
  for (Pending& p : pending) {
    if (p.source && p.source->num_frames() < frames)
      fail(p.where + ": has " + std::to_string(p.source->num_frames()) + " frames, /frame_count asks for " +
           std::to_string(frames));
    const bool rigid = !p.source;
    if (rigid)
      p.source = opened_at(p.where, [&] {
        return make_rigid_mesh(p.name, p.origin, std::move(p.mesh), std::move(p.motion), frames);
      });
    scene_parts.push_back({p.name, std::move(p.source), rigid});
  }
  return compose_parts(std::move(scene_parts), frames);
}

Scene open_descriptor(const std::filesystem::path& file, const nlohmann::json& overrides) {
  std::ifstream in(file);
  if (!in) fail(file.string() + ": cannot open scene descriptor");
  const nlohmann::json j = parse_json_file(in, file.string());
  if (!j.is_object()) fail(file.string() + ": a scene descriptor must be a JSON object");
  const DescriptorObject root(j, file.string() + ": ",
                              {"description", "generator", "params", "frames", "boxes", "animation", "keyframes",
                               "crowd", "parts", "frame_count", "objects", "queries", "placement"});
  Scene s;
  s.name = file.stem().string();
  if (j.contains("description")) s.description = root.text("description");
  int kinds = 0;
  for (const char* kind : {"generator", "frames", "boxes", "animation", "keyframes", "crowd", "parts"})
    kinds += root.has(kind);
  if (kinds != 1)
    fail(file.string() +
         ": needs exactly one of /generator (procedural), /frames (mesh or box frame directory), /boxes (box "
         "frame directory), /animation (animated file), /keyframes (per-vertex keyframe file), /crowd (instances "
         "of an animated file) or /parts (a scene of parts)");
  if (root.has("params") && !root.has("generator")) fail(file.string() + ": /params: only valid with /generator");
  if (root.has("frame_count") && !root.has("parts")) fail(file.string() + ": /frame_count: only valid with /parts");
  if (!overrides.empty() && !root.has("generator") && !root.has("crowd"))
    fail_usage(file.string() + ": parameters can only be set on a procedural scene or a crowd");
  s.source = root.has("parts") ? open_parts(root, file)
                                : open_source(root, file, s.name, file.string(), overrides, &s.parameters);
  if (j.contains("objects") || j.contains("queries"))
    s.source = declare_queries(std::move(s.source), j, file.string());
  if (root.has("placement")) {
    const DescriptorObject p = root.object("placement", {"scale", "offset"});
    nlohmann::json keys = nlohmann::json::object();
    for (const char* key : {"scale", "offset"})
      if (p.has(key)) keys[std::string("placement.") + key] = p.raw(key);
    s.source = place_scene(std::move(s.source), parse_placement(keys, file.string() + ": /"));
  }
  // The descriptor's own description states its default sizes; with overrides the
  // generated source describes what actually runs.
  if (s.description.empty() || !overrides.empty()) s.description = s.source->describe();
  if (!overrides.empty()) {
    s.overrides = overrides;
    s.description += " (" + scene_label(s.name, overrides) + ")";
  }
  return s;
}

Scene open_unplaced(const std::string& spec, const std::filesystem::path& scenes_dir,
                    const nlohmann::json& overrides) {
  const std::filesystem::path p(spec);
  if (std::filesystem::is_directory(p)) {
    if (!overrides.empty()) fail_usage(spec + ": parameters can only be set on a procedural scene");
    Scene s;
    // "frames/" names the directory "frames", not "".
    const std::filesystem::path named = p.has_filename() ? p : p.parent_path();
    s.name = named.filename().string();
    s.source = open_frame_directory(p);
    s.description = s.source->describe();
    return s;
  }
  if (p.extension() == ".json") return open_descriptor(p, overrides);
  const auto named = scenes_dir / (spec + ".json");
  if (std::filesystem::is_regular_file(named)) return open_descriptor(named, overrides);
  std::string known;
  for (const auto& n : list_scenes(scenes_dir)) known += (known.empty() ? "" : ", ") + n;
  fail_usage("unknown scene '" + spec + "': not a directory of mesh or box frames, not a .json descriptor, and not in " +
             scenes_dir.string() + " (known: " + known + ")");
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
  // placement.* applies to every kind of scene, after the descriptor's own placement; the
  // other keys are the generator's.
  nlohmann::json rest = nlohmann::json::object(), placement = nlohmann::json::object();
  for (auto it = overrides.begin(); it != overrides.end(); ++it)
    (it.key().rfind("placement.", 0) == 0 ? placement : rest)[it.key()] = it.value();
  for (auto it = placement.begin(); it != placement.end(); ++it)
    if (it.key() != "placement.scale" && it.key() != "placement.offset")
      fail_usage("--set " + it.key() + ": unknown (known: placement.scale, placement.offset)");
  Scene s = open_unplaced(spec, scenes_dir, rest);
  if (placement.empty()) return s;
  s.source = place_scene(std::move(s.source), parse_placement(placement, "--set "));
  s.overrides.update(placement);
  s.description = s.source->describe() + " (" + scene_label(s.name, s.overrides) + ")";
  return s;
}

}  // namespace cdb
