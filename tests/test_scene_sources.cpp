// Scene sources beyond generators and animated files: per-vertex keyframe files (MD2), rigid
// meshes moved by a per-frame transform, scenes of parts, crowds of an animated character,
// data extracted from package archives, and the descriptor errors of all of them. The files
// come from Debian packages (assimp-testmodels, glmark2-data, libcgal-demo) that CI installs
// with scripts/install-deps.sh --scenes --scenes-extra; a missing file fails the test.
#include <gtest/gtest.h>
#include <unistd.h>

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "cdbench/geometry/float_spacing.h"
#include "scenes/load/animated_mesh.h"
#include "scenes/load/archive_cache.h"
#include "scenes/load/keyframe_mesh.h"
#include "scenes/load/rigid_mesh.h"
#include "scenes/load/scene.h"
#include "error_of.h"

namespace cdb::test {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const fs::path kSydney = "/usr/share/assimp/models/MD2/sydney.md2";
const fs::path kBcn = "/usr/share/assimp/models/X/BCN_Epileptic.X";
const fs::path kCgalData = "/usr/share/doc/libcgal-dev/data.tar.gz";
const fs::path kBunny = "/usr/share/glmark2/models/bunny.obj";

// A packaged file the test needs: its absence is a failure that says how to install it.
::testing::AssertionResult installed(const fs::path& file, const char* package, const char* flag) {
  if (fs::exists(file)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << file << " is missing: install the Debian package " << package
                                       << " (scripts/install-deps.sh " << flag << ")";
}

// A scratch directory with descriptors and meshes, removed at the end; the scene cache
// points into it so that tests never write to the user's cache.
struct Scratch {
  fs::path dir = fs::temp_directory_path() / ("cdb_sources_" + std::to_string(::getpid()));
  Scratch() {
    fs::create_directories(dir);
    ::setenv("CDBENCH_CACHE", (dir / "cache").c_str(), 1);
  }
  ~Scratch() { fs::remove_all(dir); }
  fs::path descriptor(const json& j, const std::string& name = "scene.json") const {
    const fs::path f = dir / name;
    std::ofstream(f) << j.dump(1);
    return f;
  }
  std::string error(const json& j) const {
    const fs::path f = descriptor(j);
    return error_of([&] { open_scene(f.string(), dir); });
  }
};

// A unit cube as OFF: 8 vertices, 6 quads (12 triangles).
fs::path write_cube_off(const fs::path& dir) {
  const fs::path f = dir / "cube.off";
  std::ofstream(f) << "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";
  return f;
}

// ---- MD2 keyframes ----

// Positions of keyframe k by a separate import, per triangle corner, node transforms applied.
std::vector<aiVector3D> corners_of_keyframe(uint32_t k) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_IMPORT_MD2_KEYFRAME, int(k));
  const aiScene* sc = importer.ReadFile(kSydney.string(), aiProcess_Triangulate);
  EXPECT_TRUE(sc) << importer.GetErrorString();
  std::vector<aiVector3D> out;
  if (!sc) return out;
  const aiMesh* m = sc->mMeshes[sc->mRootNode->mMeshes[0]];
  for (unsigned f = 0; f < m->mNumFaces; ++f)
    for (int c = 0; c < 3; ++c) out.push_back(sc->mRootNode->mTransformation * m->mVertices[m->mFaces[f].mIndices[c]]);
  return out;
}

TEST(KeyframeMesh, SydneyHas198KeyframesOnOneTopology) {
  ASSERT_TRUE(installed(kSydney, "assimp-testmodels", "--scenes"));
  EXPECT_EQ(keyframes_in_header(kSydney), 198u);
  const Scene s = open_scene("sydney-md2", default_scenes_dir());
  const Topology& t = s.source->topology();
  ASSERT_EQ(s.source->num_frames(), 198u);
  ASSERT_EQ(t.faces.size(), 679u);
  ASSERT_EQ(t.objects.size(), 1u);
  EXPECT_EQ(t.objects[0].name, "sydney");
  EXPECT_FALSE(t.objects[0].rigid);
  // MD2 gives each corner its own vertex; welding finds the shared ones.
  EXPECT_LT(t.num_vertices, 3u * 679u / 2);
  const std::vector<Tri> faces = t.faces;
  std::vector<vec3f> first, v;
  s.source->frame(0, first);
  uint32_t moved_frames = 0;
  for (uint32_t k : {0u, 1u, 57u, 120u, 197u}) {
    s.source->frame(k, v);
    ASSERT_EQ(v.size(), t.num_vertices) << "frame " << k;
    const auto want = corners_of_keyframe(k);
    ASSERT_EQ(want.size(), 3 * faces.size());
    for (size_t f = 0; f < faces.size(); ++f) {
      const uint32_t corner[3] = {faces[f].v0, faces[f].v1, faces[f].v2};
      for (int c = 0; c < 3; ++c) {
        const vec3f& p = v[corner[c]];
        const aiVector3D& q = want[3 * f + c];
        ASSERT_TRUE(p.x == q.x && p.y == q.y && p.z == q.z) << "frame " << k << " face " << f << " corner " << c;
      }
    }
    double moved = 0;
    for (size_t i = 0; i < v.size(); ++i) moved = std::max(moved, double(std::abs(v[i].x - first[i].x)));
    moved_frames += moved > 0.1;
  }
  EXPECT_EQ(moved_frames, 4u) << "keyframes 1, 57, 120 and 197 should differ from keyframe 0";
  // Topology is the same after reading frames.
  ASSERT_EQ(s.source->topology().faces.size(), faces.size());
  EXPECT_EQ(std::memcmp(s.source->topology().faces.data(), faces.data(), faces.size() * sizeof(Tri)), 0);
}

TEST(KeyframeMesh, RangeAndFrameErrorsNameTheFileAndKeyframe) {
  ASSERT_TRUE(installed(kSydney, "assimp-testmodels", "--scenes"));
  Scratch s;
  auto with = [&](json k) {
    k["file"] = kSydney.string();
    return s.error({{"keyframes", k}});
  };
  EXPECT_NE(with({{"first", 198}}).find("sydney.md2: first keyframe 198 out of range (the file has 198 keyframes)"),
            std::string::npos);
  EXPECT_NE(with({{"first", 190}, {"frames", 10}}).find("keyframes 190..199 asked for, the file has 198"),
            std::string::npos);
  EXPECT_NE(with({{"frames", "all"}}).find("/keyframes/frames: must be an integer"), std::string::npos);
  EXPECT_NE(with({{"speed", 2}}).find("/keyframes/speed: unknown key (file, first, frames, subframes)"), std::string::npos);
  const Scene ten = open_scene(s.descriptor({{"keyframes", {{"file", kSydney.string()}, {"first", 40}, {"frames", 10}}}}).string(),
                               s.dir);
  EXPECT_EQ(ten.source->num_frames(), 10u);
  std::vector<vec3f> v;
  EXPECT_NE(error_of([&] { ten.source->frame(10, v); }).find("frame 10 out of range (10 frames)"), std::string::npos);
}

TEST(KeyframeMesh, SubframesBlendNeighbouringKeyframes) {
  ASSERT_TRUE(installed(kSydney, "assimp-testmodels", "--scenes"));
  auto s = open_keyframe_mesh({kSydney, 10, 9, 4});  // keyframes 10, 11, 12 and 3 blends between each
  ASSERT_EQ(s->num_frames(), 9u);
  auto whole = open_keyframe_mesh({kSydney, 10, 3, 1});
  std::vector<vec3f> k10, k11, k12, v;
  whole->frame(0, k10);
  whole->frame(1, k11);
  whole->frame(2, k12);
  s->frame(4, v);
  EXPECT_EQ(std::memcmp(v.data(), k11.data(), v.size() * sizeof(vec3f)), 0) << "frame 4 is keyframe 11";
  s->frame(8, v);
  EXPECT_EQ(std::memcmp(v.data(), k12.data(), v.size() * sizeof(vec3f)), 0) << "frame 8 is keyframe 12";
  s->frame(2, v);
  double moved = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    EXPECT_NEAR(v[i].x, 0.5 * (k10[i].x + k11[i].x), 1e-5) << "vertex " << i;
    EXPECT_NEAR(v[i].y, 0.5 * (k10[i].y + k11[i].y), 1e-5) << "vertex " << i;
    EXPECT_NEAR(v[i].z, 0.5 * (k10[i].z + k11[i].z), 1e-5) << "vertex " << i;
    moved = std::max(moved, double(std::abs(k11[i].x - k10[i].x)));
  }
  EXPECT_GT(moved, 0.1) << "keyframes 10 and 11 should differ";
  EXPECT_NE(error_of([&] { open_keyframe_mesh({kSydney, 190, 30, 4}); }).find("keyframes 190..198 asked for"),
            std::string::npos);
  EXPECT_EQ(open_keyframe_mesh({kSydney, 0, 0, 3})->num_frames(), 197u * 3 + 1);
}

// ---- rigid meshes ----

// The pose a motion gives, computed here from Rodrigues' formula apart from the loader.
vec3f moved(const scene::dvec3& p, const scene::dvec3& axis, double angle, const scene::dvec3& pivot,
            const scene::dvec3& t) {
  const scene::dvec3 k = scene::normalized(axis), q = p - pivot;
  const double c = std::cos(angle), s = std::sin(angle);
  const scene::dvec3 r = c * q + s * scene::cross(k, q) + (1 - c) * scene::dot(k, q) * k;
  const scene::dvec3 x = r + pivot + t;
  return {float(x.x), float(x.y), float(x.z)};
}

TEST(RigidMesh, ParametricMotionIsTheTransformOfTheMesh) {
  Scratch s;
  write_cube_off(s.dir);
  const json d = {{"frame_count", 12},
                  {"parts", {{{"name", "box"},
                              {"mesh", {{"file", "cube.off"}, {"scale", 2.0}, {"center", true}}},
                              {"motion", {{"fps", 10}, {"position", {1, 2, 3}}, {"velocity", {0.5, 0, -1}},
                                          {"axis", {1, 1, 0}}, {"angle", 0.3}, {"angular_velocity", 2.0},
                                          {"pivot", {0.5, 0, 0}}}}}}}};
  const Scene scene = open_scene(s.descriptor(d).string(), s.dir);
  const Topology& t = scene.source->topology();
  ASSERT_EQ(scene.source->num_frames(), 12u);
  ASSERT_EQ(t.faces.size(), 12u);
  EXPECT_EQ(t.num_vertices, 8u) << "the cube's corners are welded";
  ASSERT_EQ(t.objects.size(), 1u);
  EXPECT_EQ(t.objects[0].name, "box");
  EXPECT_TRUE(t.objects[0].rigid);
  EXPECT_EQ(t.objects[0].first_face, 0u);
  EXPECT_EQ(t.objects[0].num_faces, 12u);
  // The placed mesh is the cube centred and doubled: corners at +-1.
  std::vector<vec3f> v0, v;
  const StaticMesh placed = load_static_mesh(s.dir / "cube.off", 2.0, true);
  for (const auto& p : placed.positions)
    EXPECT_TRUE(std::abs(p.x) == 1 && std::abs(p.y) == 1 && std::abs(p.z) == 1) << p.x << " " << p.y << " " << p.z;
  for (uint32_t k = 0; k < 12; ++k) {
    scene.source->frame(k, v);
    const double sec = k / 10.0;
    for (size_t i = 0; i < v.size(); ++i) {
      const vec3f want = moved(placed.positions[i], {1, 1, 0}, 0.3 + 2.0 * sec, {0.5, 0, 0},
                               scene::dvec3{1, 2, 3} + sec * scene::dvec3{0.5, 0, -1});
      EXPECT_NEAR(v[i].x, want.x, 1e-6) << "frame " << k << " vertex " << i;
      EXPECT_NEAR(v[i].y, want.y, 1e-6) << "frame " << k << " vertex " << i;
      EXPECT_NEAR(v[i].z, want.z, 1e-6) << "frame " << k << " vertex " << i;
    }
    // Rigid: every edge keeps its length.
    if (k == 0) v0 = v;
    for (const Tri& f : t.faces) {
      auto len = [](vec3f a, vec3f b) { return std::hypot(a.x - b.x, a.y - b.y, a.z - b.z); };
      EXPECT_NEAR(len(v[f.v0], v[f.v1]), len(v0[f.v0], v0[f.v1]), 1e-5);
    }
  }
}

// Four cubes that only the file's node transforms keep apart.
TEST(RigidMesh, BlendFileMeshesArePlacedByTheirNodes) {
  const fs::path file = "/usr/share/assimp/models/BLEND/4Cubes4Mats_248.blend";
  ASSERT_TRUE(installed(file, "assimp-testmodels", "--scenes"));
  const StaticMesh m = load_static_mesh(file, 1.0, false);
  EXPECT_EQ(m.faces.size(), 4u * 12u);
  EXPECT_EQ(m.positions.size(), 4u * 8u) << "cubes at one place would weld to 8 vertices";
}

TEST(RigidMesh, KeyedMotionInterpolatesBetweenKeysAndHoldsAtTheEnds) {
  RigidMotion m;
  m.keys = {{2, {0, 0, 0}, {0, 0, 1}, 0.0}, {6, {4, 0, 0}, {0, 0, 1}, 1.0}, {10, {4, 8, 0}, {1, 0, 0}, 0.5}};
  const scene::dvec3 p{1, 0, 0};
  auto at = [&](uint32_t k) { return rigid_pose(m, k).apply(p); };
  EXPECT_NEAR(at(0).x, 1, 1e-12);  // before the first key: the first pose
  EXPECT_NEAR(at(4).x, 2 + std::cos(0.5), 1e-12);  // halfway: translation 2, angle 0.5 about z
  EXPECT_NEAR(at(4).y, std::sin(0.5), 1e-12);
  // Between keys of different axes the rotation is the slerp of the two: at the keys exact.
  const auto k10 = at(10), late = at(30);
  EXPECT_NEAR(k10.x, 5, 1e-12);
  EXPECT_NEAR(late.x, k10.x, 1e-12);
  EXPECT_NEAR(late.y, k10.y, 1e-12);
  const auto k8 = at(8);
  EXPECT_GT(k8.y, 0);
  EXPECT_LT(k8.y, 8);
}

TEST(ComposedScene, PartsAreConcatenatedInOrderWithTheirRigidFlags) {
  Scratch s;
  write_cube_off(s.dir);
  const json d = {{"parts",
                   {{{"name", "sheet"}, {"generator", "cloth-wave"}, {"params", {{"res", 5}, {"frames", 4}}}},
                    {{"name", "box"}, {"mesh", {{"file", "cube.off"}}},
                     {"motion", {{"velocity", {0, -3, 0}}, {"fps", 4}}}},
                    {{"name", "still"}, {"mesh", {{"file", "cube.off"}, {"scale", 0.5}}}}}},
                  {"queries", {{"self", {"sheet"}}, {"inter", json::array({json::array({"sheet", "box"}), json::array({"box", "still"})})}}}};
  const Scene scene = open_scene(s.descriptor(d).string(), s.dir);
  const Topology& t = scene.source->topology();
  EXPECT_EQ(scene.source->num_frames(), 4u);  // the cloth's count
  ASSERT_EQ(t.objects.size(), 3u);
  EXPECT_EQ(t.objects[0].name, "sheet");
  EXPECT_FALSE(t.objects[0].rigid);
  EXPECT_EQ(t.objects[0].first_face, 0u);
  EXPECT_EQ(t.objects[0].num_faces, 32u);
  EXPECT_TRUE(t.objects[1].rigid);
  EXPECT_EQ(t.objects[1].first_face, 32u);
  EXPECT_EQ(t.objects[1].num_faces, 12u);
  EXPECT_TRUE(t.objects[2].rigid);
  EXPECT_EQ(t.objects[2].first_face, 44u);
  EXPECT_EQ(t.faces.size(), 56u);
  EXPECT_EQ(t.num_vertices, 25u + 8u + 8u);
  ASSERT_EQ(t.queries.inter.size(), 2u);
  // The box's vertices follow the cloth's; at frame 3 (0.75 s) it has fallen 2.25 units.
  std::vector<vec3f> v;
  scene.source->frame(3, v);
  EXPECT_EQ(v[25].y, -2.25f);
  EXPECT_EQ(t.faces[32].v0 >= 25 && t.faces[43].v2 < 33, true);
}

// ---- crowds ----

TEST(Crowd, InstancesPlayTheClipAtTheirOwnPhaseOnAnOverlappingGrid) {
  ASSERT_TRUE(installed(kBcn, "assimp-testmodels", "--scenes"));
  Scratch s;
  const json d = {{"crowd", {{"animation", {{"file", kBcn.string()}, {"fps", 30}}}, {"count", 6}, {"columns", 3},
                             {"spacing", 0.7}, {"frames", 5}, {"objects", "instances"}}}};
  const Scene scene = open_scene(s.descriptor(d).string(), s.dir);
  const Topology& t = scene.source->topology();
  auto clip = open_animated_clip({kBcn, 30, 0, 0.0, 0, ""});
  const uint32_t one_faces = uint32_t(clip->topology().faces.size()), one_vertices = clip->topology().num_vertices;
  ASSERT_EQ(one_faces, 5126u);
  EXPECT_EQ(t.faces.size(), 6u * one_faces);
  EXPECT_EQ(t.num_vertices, 6u * one_vertices);
  EXPECT_EQ(scene.source->num_frames(), 5u);
  ASSERT_EQ(t.objects.size(), 6u);
  EXPECT_EQ(t.objects[4].name, "scene#4");
  EXPECT_EQ(t.objects[4].first_face, 4u * one_faces);
  // Overrides scale it: --set count=9.
  const Scene nine = open_scene(s.descriptor(d).string(), s.dir, {{"count", 9}});
  EXPECT_EQ(nine.source->topology().faces.size(), 9u * one_faces);

  std::vector<vec3f> v, rest;
  scene.source->frame(2, v);
  const double clip_len = clip->clip_seconds();
  ASSERT_GT(clip_len, 0);
  std::vector<std::vector<vec3f>> local(6);
  for (uint32_t i = 0; i < 6; ++i) {
    // Instance i = the clip at its phase, shifted by its grid offset (the same for every vertex).
    const double t_i = std::fmod(i * 0.6180339887498949 * clip_len + 2 / 30.0, clip_len);
    clip->positions_at(t_i, rest);
    const vec3f d0{v[i * one_vertices].x - rest[0].x, v[i * one_vertices].y - rest[0].y,
                   v[i * one_vertices].z - rest[0].z};
    EXPECT_NEAR(d0.y, 0, 1e-3) << "instances stand on one ground plane";
    for (uint32_t k = 0; k < one_vertices; k += 97) {
      const vec3f& p = v[i * one_vertices + k];
      ASSERT_NEAR(p.x - rest[k].x, d0.x, 1e-3) << "instance " << i << " vertex " << k;
      ASSERT_NEAR(p.z - rest[k].z, d0.z, 1e-3) << "instance " << i << " vertex " << k;
    }
    local[i] = rest;
  }
  // Different phases: instances differ in shape, not only in place.
  for (uint32_t i = 1; i < 6; ++i) {
    double diff = 0;
    for (uint32_t k = 0; k < one_vertices; ++k) diff = std::max(diff, double(std::abs(local[i][k].y - local[0][k].y)));
    EXPECT_GT(diff, 1e-3) << "instance " << i << " moves like instance 0";
  }
  // Neighbours overlap: the boxes of instances 0 and 1 intersect.
  auto box = [&](uint32_t i) {
    vec3f lo = v[i * one_vertices], hi = lo;
    for (uint32_t k = 0; k < one_vertices; ++k) {
      const vec3f& p = v[i * one_vertices + k];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    return std::make_pair(lo, hi);
  };
  const auto [lo0, hi0] = box(0);
  const auto [lo1, hi1] = box(1);
  EXPECT_TRUE(lo0.x <= hi1.x && lo1.x <= hi0.x && lo0.z <= hi1.z && lo1.z <= hi0.z);
}

// ---- packaged static scans ----

TEST(PackagedScans, ArchiveMemberIsExtractedOnceIntoTheCache) {
  ASSERT_TRUE(installed(kCgalData, "libcgal-demo", "--scenes-extra"));
  Scratch s;
  const fs::path f = extract_from_archive(kCgalData, "data/meshes/elephant.off");
  EXPECT_EQ(f.string().rfind((s.dir / "cache").string(), 0), 0u) << f;
  std::ifstream in(f);
  std::string magic;
  size_t vertices = 0, faces = 0;
  in >> magic >> vertices >> faces;
  EXPECT_EQ(magic, "OFF");
  EXPECT_EQ(faces, 5558u);
  const auto when = fs::last_write_time(f);
  EXPECT_EQ(extract_from_archive(kCgalData, "data/meshes/elephant.off"), f);
  EXPECT_EQ(fs::last_write_time(f), when) << "extracted again";
  EXPECT_NE(error_of([&] { extract_from_archive(kCgalData, "data/meshes/unicorn.off"); })
                .find("data.tar.gz: no member 'data/meshes/unicorn.off' in this archive"),
            std::string::npos);
  EXPECT_NE(error_of([&] { extract_from_archive(kCgalData, "../etc/passwd"); }).find("must be a relative path"),
            std::string::npos);
}

TEST(PackagedScans, SceneDescriptorsOpenWithTheirDeclaredSizes) {
  ASSERT_TRUE(installed(kCgalData, "libcgal-demo", "--scenes-extra"));
  ASSERT_TRUE(installed(kBunny, "glmark2-data", "--scenes-extra"));
  Scratch s;
  const Scene ea = open_scene("elephant-armadillo", default_scenes_dir());
  const Topology& t = ea.source->topology();
  ASSERT_EQ(t.objects.size(), 2u);
  EXPECT_EQ(t.objects[0].num_faces, 88928u);  // refined_elephant.off
  EXPECT_EQ(t.objects[1].num_faces, 52000u);  // armadillo.off
  EXPECT_TRUE(t.objects[0].rigid && t.objects[1].rigid);
  EXPECT_TRUE(t.queries.declared);
  const Scene bd = open_scene("bunny-drop", default_scenes_dir());
  const auto& o = bd.source->topology().objects;
  ASSERT_EQ(o.size(), 2u);
  EXPECT_FALSE(o[0].rigid);
  EXPECT_TRUE(o[1].rigid);
  EXPECT_EQ(o[1].num_faces, 69666u);  // glmark2's bunny.obj
}

// ---- descriptor errors ----

TEST(SceneDescriptors, ErrorsNameTheFileAndJsonPath) {
  Scratch s;
  write_cube_off(s.dir);
  const std::string file = (s.dir / "scene.json").string();
  const json cube = {{"file", "cube.off"}};
  auto part = [&](json p) {
    p["name"] = "box";
    return s.error({{"frame_count", 3}, {"parts", json::array({p})}});
  };
  auto has = [&](const std::string& message, const std::string& want) {
    EXPECT_NE(message.find(want), std::string::npos) << "message: " << message << "\nwanted: " << want;
  };
  // Unknown keys, at every level.
  has(s.error({{"parts", json::array()}, {"colour", 1}}), file + ": /colour: unknown key");
  has(part({{"mesh", cube}, {"spin", 1}}), file + ": /parts/0/spin: unknown key (name, generator, params,");
  has(part({{"mesh", {{"file", "cube.off"}, {"size", 2}}}}), file + ": /parts/0/mesh/size: unknown key");
  has(part({{"mesh", cube}, {"motion", {{"speed", 1}}}}), file + ": /parts/0/motion/speed: unknown key");
  has(part({{"mesh", cube}, {"motion", {{"keys", {{{"frame", 0}, {"turn", 1}}}}}}}),
      file + ": /parts/0/motion/keys/0/turn: unknown key (frame, position, axis, angle)");
  // Wrong types.
  has(part({{"mesh", {{"file", 3}}}}), file + ": /parts/0/mesh/file: must be a string");
  has(part({{"mesh", {{"file", "cube.off"}, {"scale", "big"}}}}), file + ": /parts/0/mesh/scale: must be a number");
  has(part({{"mesh", {{"file", "cube.off"}, {"center", 1}}}}), file + ": /parts/0/mesh/center: must be true or false");
  has(part({{"mesh", cube}, {"motion", {{"velocity", {1, 2}}}}}), file + ": /parts/0/motion/velocity: must be [x, y, z]");
  has(part({{"mesh", cube}, {"motion", {{"velocity", {1, "a", 2}}}}}), file + ": /parts/0/motion/velocity/1: must be a number");
  has(part({{"mesh", cube}, {"motion", {{"axis", {0, 0, 0}}}}}), file + ": /parts/0/motion/axis: must not be zero");
  has(part({{"mesh", cube}, {"motion", {{"keys", {{{"frame", 4}}, {{"frame", 2}}}}}}}),
      file + ": /parts/0/motion/keys/1/frame: must be >= 0 and after the previous key's");
  has(part({{"mesh", cube}, {"motion", {{"keys", {{{"frame", 0}}}}, {"velocity", {1, 0, 0}}}}}),
      file + ": /parts/0/motion/velocity: not with keys");
  has(s.error({{"frame_count", "many"}, {"parts", {{{"name", "box"}, {"mesh", cube}}}}}),
      file + ": /frame_count: must be an integer");
  has(s.error({{"parts", {{{"name", "box"}, {"mesh", cube}}}}}), file + ": /frame_count: required when every part is a rigid mesh");
  has(s.error({{"parts", {{{"name", 7}, {"mesh", cube}}}}}), file + ": /parts/0/name: must be a string");
  has(s.error({{"parts", "cube"}}), file + ": /parts: must be a non-empty array");
  has(s.error({{"frame_count", 2}, {"parts", {{{"name", "a"}, {"mesh", cube}}, {{"name", "a"}, {"mesh", cube}}}}}),
      file + ": /parts/1/name: 'a' names an earlier part too");
  has(part({{"mesh", cube}, {"generator", "flag"}}), file + ": /parts/0: needs exactly one of");
  has(part({{"mesh", {{"file", "cube.off"}, {"archive", "x.tar.gz"}}}}), file + ": /parts/0/mesh: needs exactly one of file or archive");
  // Frame counts of parts.
  const json wave3 = {{"name", "a"}, {"generator", "cloth-wave"}, {"params", {{"res", 3}, {"frames", 3}}}};
  json wave5 = {{"name", "b"}, {"generator", "cloth-wave"}, {"params", {{"res", 3}, {"frames", 5}}}};
  has(s.error({{"parts", {wave3, wave5}}}), file + ": /frame_count: required when the parts' frame counts differ (a 3, b 5)");
  has(s.error({{"frame_count", 4}, {"parts", {wave3, wave5}}}), file + ": /parts/0: has 3 frames, /frame_count asks for 4");
  EXPECT_EQ(open_scene(s.descriptor({{"frame_count", 3}, {"parts", {wave3, wave5}}}).string(), s.dir).source->num_frames(), 3u);
  wave5["params"]["colour"] = 1;
  has(s.error({{"parts", {wave3, wave5}}}), file + ": /parts/1: generator 'cloth-wave', parameter 'colour': unknown parameter");
  // Missing files, with the package that provides them where there is one.
  has(part({{"mesh", {{"file", "nothing.off"}}}}), file + ": /parts/0/mesh/file: " + (s.dir / "nothing.off").string() + ": no such file");
  has(part({{"mesh", {{"file", "/usr/share/glmark2/models/dragon.obj"}}}}),
      "/parts/0/mesh/file: /usr/share/glmark2/models/dragon.obj: no such file (it ships with the Debian package "
      "glmark2-data: run scripts/install-deps.sh --scenes-extra)");
  has(part({{"mesh", {{"archive", "/usr/share/doc/libcgal-dev/nodata.tar.gz"}, {"member", "a.off"}}}}),
      "/parts/0/mesh/archive: /usr/share/doc/libcgal-dev/nodata.tar.gz: no such file (it ships with the Debian "
      "package libcgal-demo: run scripts/install-deps.sh --scenes-extra)");
  has(s.error({{"keyframes", {{"file", "/usr/share/assimp/models/MD2/none.md2"}}}}),
      file + ": /keyframes/file: /usr/share/assimp/models/MD2/none.md2: no such file (it ships with the Debian package "
             "assimp-testmodels: run scripts/install-deps.sh --scenes)");
  // Crowds.
  has(s.error({{"crowd", {{"count", 4}}}}), file + ": /crowd/animation: required");
  has(s.error({{"crowd", {{"animation", {{"file", "cube.off"}, {"frames", 3}}}}}}),
      file + ": /crowd/animation/frames: unknown key (file, fps, start, clip)");
  has(s.error({{"crowd", {{"animation", {{"file", "cube.off"}}}, {"count", -1}}}}), file + ": /crowd/count: must be an integer");
  has(s.error({{"crowd", {{"animation", {{"file", "cube.off"}}}, {"up", "w"}}}}), file + ": /crowd/up: must be");
  has(s.error({{"crowd", {{"animation", {{"file", "cube.off"}}}}}}), file + ": /crowd: " + (s.dir / "cube.off").string() + ": no animation in this file");
  // Overrides are for generators and crowds only.
  const fs::path rigid = s.descriptor({{"frame_count", 2}, {"parts", {{{"name", "box"}, {"mesh", cube}}}}});
  has(error_of([&] { open_scene(rigid.string(), s.dir, {{"count", 2}}); }),
      "parameters can only be set on a procedural scene or a crowd");
  // Placement: on any scene, checked.
  has(error_of([&] { open_scene(rigid.string(), s.dir, {{"placement.scale", 0}}); }), "--set placement.scale: must be positive");
  has(error_of([&] { open_scene(rigid.string(), s.dir, {{"placement.offset", {1, 2}}}); }),
      "--set placement.offset: must be a number or [x, y, z]");
  has(error_of([&] { open_scene(rigid.string(), s.dir, {{"placement.turn", 1}}); }),
      "--set placement.turn: unknown (known: placement.scale, placement.offset)");
  has(s.error({{"frame_count", 2}, {"parts", {{{"name", "box"}, {"mesh", cube}}}}, {"placement", {{"spin", 1}}}}),
      file + ": /placement/spin: unknown key (scale, offset)");
}

// ---- placement ----

// placement.scale and placement.offset move a scene in double, on top of the descriptor's
// own placement, and name the scene.
TEST(Placement, ScalesThenMovesInDoubleOnTopOfTheDescriptors) {
  Scratch s;
  const json wave = {{"generator", "cloth-wave"}, {"params", {{"res", 4}, {"frames", 2}}}};
  const Scene plain = open_scene(s.descriptor(wave).string(), s.dir);
  json placed_wave = wave;
  placed_wave["placement"] = {{"scale", 2.0}};
  const Scene placed = open_scene(s.descriptor(placed_wave).string(), s.dir,
                                  {{"placement.scale", 1e-3}, {"placement.offset", {1e12, 0, -1e7}}});
  EXPECT_NE(placed.description.find("placement.offset"), std::string::npos) << placed.description;
  std::vector<vec3d> a, b;
  plain.source->positions(1, a);
  placed.source->positions(1, b);
  ASSERT_EQ(a.size(), b.size());
  for (size_t v = 0; v < a.size(); ++v) {
    EXPECT_EQ(b[v].x, 1e-3 * (2.0 * a[v].x) + 1e12);
    EXPECT_EQ(b[v].y, 1e-3 * (2.0 * a[v].y));
    EXPECT_EQ(b[v].z, 1e-3 * (2.0 * a[v].z) - 1e7);
  }
}

// Float's spacing holds every shipped scene's features (no warning), and stops holding
// them once the scene is moved far out.
TEST(Placement, ShippedScenesDrawNoFloatSpacingWarning) {
  size_t checked = 0;
  for (const std::string& name : list_scenes(default_scenes_dir())) {
    const Scene scene = open_scene(name, default_scenes_dir());
    EXPECT_EQ(float_spacing_warning(*scene.source, 0, false), "") << name;
    ++checked;
  }
  EXPECT_GE(checked, 20u);
  const Scene far = open_scene("funnel", default_scenes_dir(), {{"placement.offset", 1e7}});
  EXPECT_NE(float_spacing_warning(*far.source, 0, false), "");
  EXPECT_EQ(float_spacing_warning(*far.source, 0, true), "");
}

}  // namespace
}  // namespace cdb::test
