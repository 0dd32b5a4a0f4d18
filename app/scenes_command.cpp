#include "scenes_command.h"
#include "path_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <regex>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "cdbench/geometry/float_spacing.h"
#include "scenes/load/frames_descriptor.h"
#include "scenes/load/obj_sequence.h"
#include "scenes/load/scene.h"
#include "scenes/load/scene_label.h"
#include "options.h"

namespace cdb {

ScenesCommand add_scenes_command(CLI::App& app, ScenesOptions& s) {
  auto* scenes = app.add_subcommand("scenes", "list, describe and generate scenes");
  scenes->add_option("--scenes-dir", s.scenes_dir, "where named scenes live");
  ScenesCommand c;
  c.list = scenes->add_subcommand("list", "list scenes with sizes");
  c.info = scenes->add_subcommand("info", "a scene's size, bounding box and motion per frame");
  // The scene as run and verify take it (--scene) or as the first argument.
  c.info->add_option("scene,--scene", s.scene, "scene name, .json descriptor or mesh directory")->required();
  c.info->add_option("--set", s.sets, "override a generator parameter: key=value (repeatable)");
  c.info->add_flag("--json", s.json, "JSON instead of text: one object with the same fields");
  c.generate = scenes->add_subcommand("generate", "write a scene's frames as OBJ files");
  c.generate->add_option("scene,--scene", s.scene, "scene name or .json descriptor")->required();
  c.generate->add_option("--set", s.sets, "override a generator parameter: key=value, e.g. res=128 frames=10");
  auto* out_option = c.generate->add_option("--out", s.out_dir, "output directory (frame_0000.obj, ...)")
                         ->required()
                         ->check(non_empty_path());
  c.generate
      ->add_flag("--overwrite", s.overwrite,
                 "let --out replace the frames an earlier generation left there (and remove those past the new "
                 "frame count)")
      ->needs(out_option);
  // Also after the subcommand, where run and verify take it: `scenes info funnel
  // --scenes-dir X` as well as `scenes --scenes-dir X info funnel`.
  for (CLI::App* sub : {c.list, c.info, c.generate})
    sub->add_option("--scenes-dir", s.scenes_dir, "where named scenes live");
  scenes->require_subcommand(1);
  return c;
}

int scenes_list(const ScenesOptions& opts) {
  const auto dir = scenes_dir(opts.scenes_dir);
  // A directory that is not there lists nothing, which reads as "no scenes": a mistake in
  // the call, named with where the directory came from.
  std::error_code ec;
  if (!std::filesystem::is_directory(dir, ec))
    fail_usage((opts.scenes_dir.empty() ? "CDBENCH_SCENES=" : "--scenes-dir ") + dir.string() + ": " +
               (std::filesystem::exists(dir, ec) ? "not a directory" : "no such directory") +
               "; name the directory that holds the scene descriptors (*.json)");
  // A scene whose data is not installed (e.g. assimp-testmodels) is listed with the reason,
  // and the others still are.
  for (const auto& name : list_scenes(dir)) {
    try {
      const Scene scene = open_scene(name, dir);
      std::printf("%-14s %9zu triangles %5u frames  %s\n", name.c_str(),
                  scene.source->topology().faces.size(), scene.source->num_frames(), scene.description.c_str());
    } catch (const Error& e) {
      std::printf("%-14s unavailable: %s\n", name.c_str(), e.what());
    }
  }
  return 0;
}

namespace {

// The frame number of a file this command writes (frame_0000.obj, ...), none for others.
std::optional<uint64_t> written_frame(const std::filesystem::path& file) {
  static const std::regex name("frame_([0-9]{4,})\\.obj");
  std::smatch m;
  const std::string filename = file.filename().string();
  if (!std::regex_match(filename, m, name) || m[1].length() > 10) return std::nullopt;
  return std::stoull(m[1].str());
}

// --out DIR may hold only frames (and the frames' descriptor) an earlier `scenes generate`
// wrote: anything else there (another scene's meshes, notes) would be mixed into the
// sequence that reads the directory back. Those files may be another scene's, kept on
// purpose: replaced only with `overwrite`, as `run --out` replaces a file. Checked before
// any work.
void check_generate_dir(const std::filesystem::path& dir, bool overwrite) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) fail_usage("--out " + dir.string() + ": not a directory");
  size_t frames = 0;
  bool described = false;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const bool descriptor = it->path().filename() == kFramesDescriptorName;
    if (!it->is_regular_file(ec) || !(written_frame(it->path()) || descriptor))
      fail_usage("--out " + dir.string() + ": holds " + it->path().filename().string() +
                 ", which `scenes generate` did not write; give an empty or new directory");
    descriptor ? void(described = true) : void(++frames);
  }
  if (ec) fail("--out " + dir.string() + ": cannot list the directory: " + ec.message());
  if ((frames || described) && !overwrite)
    fail_usage("--out " + dir.string() + ": holds " + std::to_string(frames) +
               (frames == 1 ? " frame" : " frames") + (described ? std::string(" and ") + kFramesDescriptorName : "") +
               " an earlier generation wrote; pass --overwrite to replace them, or give an empty or new directory");
}

// Frames an earlier, longer generation left past the new last one: removed, so the
// directory holds exactly this scene's frames. Returns how many went.
size_t remove_stale_frames(const std::filesystem::path& dir, uint32_t frames) {
  namespace fs = std::filesystem;
  std::vector<fs::path> stale;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (const auto k = written_frame(it->path()); k && *k >= frames) stale.push_back(it->path());
  if (ec) fail("--out " + dir.string() + ": cannot list the directory: " + ec.message());
  for (const fs::path& file : stale)
    if (!fs::remove(file, ec) || ec)
      fail(file.string() + ": cannot remove this frame left from an earlier generation: " + ec.message());
  return stale.size();
}

}  // namespace

int scenes_generate(const ScenesOptions& opts) {
  const auto dir = scenes_dir(opts.scenes_dir);
  check_generate_dir(opts.out_dir, opts.overwrite);
  const Scene s = open_scene(opts.scene, dir, parse_set_overrides(opts.sets));
  write_obj_sequence(*s.source, opts.out_dir);
  const size_t removed = remove_stale_frames(opts.out_dir, s.source->num_frames());
  const std::filesystem::path descriptor = std::filesystem::path(opts.out_dir) / kFramesDescriptorName;
  const bool described = write_frames_descriptor(s.source->topology(), s.description, opts.out_dir);
  std::error_code ec;
  // An earlier generation's descriptor would give these frames another scene's objects.
  if (!described && std::filesystem::exists(descriptor, ec) && !std::filesystem::remove(descriptor, ec))
    fail(descriptor.string() + ": cannot remove the descriptor an earlier generation left: " + ec.message());
  std::printf("wrote %u frames of %s (%zu triangles) to %s\n", s.source->num_frames(), s.name.c_str(),
              s.source->topology().faces.size(), opts.out_dir.c_str());
  if (described)
    std::printf("wrote its objects and declared queries to %s: run it as --scene %s\n", descriptor.c_str(),
                descriptor.c_str());
  if (removed)
    std::printf("removed %zu frames left there by an earlier generation (frame %u on)\n", removed,
                s.source->num_frames());
  return 0;
}

namespace {

// One frame of a scene as `scenes info` describes it: its vertices' bounding box and, from
// the second frame on, how far they moved since the previous one.
struct FrameExtent {
  vec3d lo, hi;
  bool moved = false;  // a previous frame to move from
  double mean_move = 0, max_move = 0;
};

std::vector<FrameExtent> frame_extents(const Scene& s) {
  std::vector<FrameExtent> extents;
  std::vector<vec3d> v, prev;
  for (uint32_t f = 0; f < s.source->num_frames(); ++f) {
    s.source->positions(f, v);
    FrameExtent e;
    e.lo = v.empty() ? vec3d{} : v[0];
    e.hi = e.lo;
    double sum_move = 0;
    for (size_t k = 0; k < v.size(); ++k) {
      e.lo = {std::min(e.lo.x, v[k].x), std::min(e.lo.y, v[k].y), std::min(e.lo.z, v[k].z)};
      e.hi = {std::max(e.hi.x, v[k].x), std::max(e.hi.y, v[k].y), std::max(e.hi.z, v[k].z)};
      if (!prev.empty()) {
        const double dx = v[k].x - prev[k].x, dy = v[k].y - prev[k].y, dz = v[k].z - prev[k].z;
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        e.max_move = std::max(e.max_move, d);
        sum_move += d;
      }
    }
    e.moved = !prev.empty() && !v.empty();
    if (e.moved) e.mean_move = sum_move / double(v.size());
    extents.push_back(e);
    prev = v;
  }
  return extents;
}

std::optional<FloatSpacing> first_frame_spacing(const Scene& s) {
  if (s.source->num_frames() == 0) return std::nullopt;
  std::vector<vec3d> first;
  s.source->positions(0, first);
  return float_spacing(s.source->topology(), first, {0, 0, 0});
}

// What the text shows, as one JSON object (the numbers at full precision).
nlohmann::ordered_json scene_json(const Scene& s) {
  const Topology& topo = s.source->topology();
  const auto xyz = [](const vec3d& p) { return nlohmann::ordered_json::array({p.x, p.y, p.z}); };
  nlohmann::ordered_json parameters = nlohmann::ordered_json::array();
  for (const GeneratorParameter& p : s.parameters)
    parameters.push_back(
        {{"key", p.key}, {"kind", p.kind}, {"value", p.value}, {"default", p.fallback}, {"range", p.range}});
  nlohmann::ordered_json objects = nlohmann::ordered_json::array();
  for (const auto& ob : topo.objects)
    objects.push_back({{"name", ob.name}, {"first_face", ob.first_face}, {"faces", ob.num_faces}, {"rigid", ob.rigid}});
  nlohmann::ordered_json precision = nullptr;
  if (const auto fs = first_frame_spacing(s))
    precision = {{"median_edge", fs->median_edge}, {"float_spacing", fs->spacing}, {"largest", fs->largest},
                 {"too_coarse", fs->too_coarse()}};
  nlohmann::ordered_json frames = nlohmann::ordered_json::array();
  const std::vector<FrameExtent> extents = frame_extents(s);
  for (size_t f = 0; f < extents.size(); ++f) {
    const FrameExtent& e = extents[f];
    frames.push_back({{"frame", f},
                      {"box_min", xyz(e.lo)},
                      {"box_max", xyz(e.hi)},
                      {"motion_mean", e.moved ? nlohmann::ordered_json(e.mean_move) : nlohmann::ordered_json()},
                      {"motion_max", e.moved ? nlohmann::ordered_json(e.max_move) : nlohmann::ordered_json()}});
  }
  return {{"command", "scenes info"},
          {"scene", s.name},
          {"description", s.description},
          {"triangles", topo.faces.size()},
          {"vertices", topo.num_vertices},
          {"frames", s.source->num_frames()},
          {"parameters", std::move(parameters)},
          {"box_faces", topo.box_faces},
          {"objects", std::move(objects)},
          {"queries", queries_json(topo)},
          {"precision", std::move(precision)},
          {"frame_extents", std::move(frames)}};
}

}  // namespace

int scenes_info(const ScenesOptions& opts) {
  const auto dir = scenes_dir(opts.scenes_dir);
  const Scene s = open_scene(opts.scene, dir, parse_set_overrides(opts.sets));
  if (opts.json) {
    std::printf("%s\n", scene_json(s).dump(2).c_str());
    return 0;
  }
  const Topology& topo = s.source->topology();
  std::printf("scene       %s\n", s.name.c_str());
  std::printf("            %s\n", s.description.c_str());
  std::printf("triangles   %zu\nvertices    %u\nframes      %u\n", topo.faces.size(), topo.num_vertices,
              s.source->num_frames());
  // What --set can change, so a user need not read the generator's source.
  int key_width = 14;
  for (const GeneratorParameter& p : s.parameters) key_width = std::max(key_width, int(p.key.size()));
  for (const GeneratorParameter& p : s.parameters)
    std::printf("parameter   %-*s %-8s %s%s%s\n", key_width, p.key.c_str(), p.kind.c_str(), p.value.c_str(),
                p.value == p.fallback ? "" : (" (default " + p.fallback + ")").c_str(),
                p.range.empty() ? "" : ("  range " + p.range).c_str());
  if (topo.box_faces)
    std::printf("boxes       %u of the triangles are boxes of a box stream (min, max, max)\n", topo.box_faces);
  for (const auto& ob : topo.objects)
    std::printf("object      %-10s faces %u..%u  %s\n", ob.name.c_str(), ob.first_face,
                ob.first_face + ob.num_faces, ob.rigid ? "rigid" : "deformable");
  if (!topo.queries.declared) {
    std::printf("queries     every overlapping pair\n");
  } else {
    for (uint32_t o : topo.queries.self) std::printf("query       self %s\n", topo.objects[o].name.c_str());
    for (const auto& [a, b] : topo.queries.inter)
      std::printf("query       inter %s - %s\n", topo.objects[a].name.c_str(), topo.objects[b].name.c_str());
  }
  if (const auto fs = first_frame_spacing(s))
    std::printf("precision   median edge %.4g, float spacing %.4g at the largest coordinate %.6g%s\n", fs->median_edge,
                fs->spacing, fs->largest, fs->too_coarse() ? ": too coarse for fp32 (use --box-precision fp64)" : "");
  const std::vector<FrameExtent> extents = frame_extents(s);
  for (size_t f = 0; f < extents.size(); ++f) {
    const FrameExtent& e = extents[f];
    std::printf("frame %4zu  box [%.4g %.4g %.4g]..[%.4g %.4g %.4g]", f, e.lo.x, e.lo.y, e.lo.z, e.hi.x, e.hi.y,
                e.hi.z);
    if (e.moved) std::printf("  vertex motion mean %.4g max %.4g", e.mean_move, e.max_move);
    std::printf("\n");
  }
  return 0;
}

}  // namespace cdb
