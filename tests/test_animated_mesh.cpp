// Animated files: a hand-written glTF checked against positions known in closed form, the
// assimp test models against a plain double-precision evaluation of assimp's raw data,
// fixed topology, the descriptor key and its errors.
#include <gtest/gtest.h>
#include <unistd.h>

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "scenes/load/animated_mesh.h"
#include "scenes/load/scene.h"
#include "error_of.h"
#include "param_name.h"

namespace cdb::test {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

const fs::path kModels = "/usr/share/assimp/models";
const char* kNoModels = "assimp-testmodels is not installed (scripts/install-deps.sh --scenes installs it)";

std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = (uint32_t(bytes[i]) << 16) | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    s += abc[(n >> 18) & 63];
    s += abc[(n >> 12) & 63];
    s += i + 1 < bytes.size() ? abc[(n >> 6) & 63] : '=';
    s += i + 2 < bytes.size() ? abc[n & 63] : '=';
  }
  return s;
}

fs::path temp_dir() {
  const fs::path d = fs::temp_directory_path() / ("cdb_anim_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// Two bones: root_bone at the origin, tip_bone one up, its child. Over 1 s the root moves
// +2 in x and the tip turns 90 degrees about z. The skinned mesh has a triangle on each
// bone and one weighted half and half; a bone-less "plate" node moves +3 in z.
const std::vector<vec3f> kSkinVertices = {{-0.5f, 0, 0}, {0.5f, 0, 0},    {0, 0.5f, 0},   // root_bone
                                          {1, 1, 0},     {1, 2, 0},       {0.5f, 1.5f, 0}, // tip_bone
                                          {0, 1, 0.5f},  {0, 1, -0.5f},   {0, 0.8f, 0}};   // both
const std::vector<vec3f> kPlateVertices = {{3, 0, 0}, {4, 0, 0}, {3, 1, 0}};

fs::path write_two_bone_gltf() {
  std::vector<uint8_t> buf;
  json views = json::array(), accessors = json::array();
  auto add = [&](const void* data, size_t bytes, size_t count, int component, const char* type) {
    const size_t offset = buf.size();
    buf.insert(buf.end(), static_cast<const uint8_t*>(data), static_cast<const uint8_t*>(data) + bytes);
    while (buf.size() % 4) buf.push_back(0);
    views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}});
    accessors.push_back({{"bufferView", views.size() - 1}, {"componentType", component}, {"count", count},
                         {"type", type}});
    return accessors.size() - 1;
  };
  auto positions = [&](const std::vector<vec3f>& v) {
    const size_t a = add(v.data(), v.size() * sizeof(vec3f), v.size(), 5126, "VEC3");
    vec3f lo = v[0], hi = v[0];
    for (const vec3f& p : v)
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)},
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    accessors[a]["min"] = {lo.x, lo.y, lo.z};
    accessors[a]["max"] = {hi.x, hi.y, hi.z};
    return a;
  };
  const size_t skin_pos = positions(kSkinVertices);
  std::vector<uint16_t> joints;
  std::vector<float> weights;
  for (uint16_t v = 0; v < 9; ++v) {
    if (v < 6) {
      joints.insert(joints.end(), {uint16_t(v < 3 ? 0 : 1), 0, 0, 0});
      weights.insert(weights.end(), {1, 0, 0, 0});
    } else {
      joints.insert(joints.end(), {0, 1, 0, 0});
      weights.insert(weights.end(), {0.5f, 0.5f, 0, 0});
    }
  }
  const size_t joint_acc = add(joints.data(), joints.size() * 2, 9, 5123, "VEC4");
  const size_t weight_acc = add(weights.data(), weights.size() * 4, 9, 5126, "VEC4");
  const size_t plate_pos = positions(kPlateVertices);
  // Column-major: identity, and a translation by -1 in y (the inverse of tip_bone's bind pose).
  float ibm[32] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
  const size_t ibm_acc = add(ibm, sizeof ibm, 2, 5126, "MAT4");
  const float times[2] = {0, 1};
  const size_t time_acc = add(times, sizeof times, 2, 5126, "SCALAR");
  accessors[time_acc]["min"] = {0.0};
  accessors[time_acc]["max"] = {1.0};
  const float s = float(std::sqrt(0.5));
  const float turn[8] = {0, 0, 0, 1, 0, 0, s, s};
  const size_t turn_acc = add(turn, sizeof turn, 2, 5126, "VEC4");
  const float slide[6] = {0, 0, 0, 2, 0, 0};
  const size_t slide_acc = add(slide, sizeof slide, 2, 5126, "VEC3");
  const float lift[6] = {0, 0, 0, 0, 0, 3};
  const size_t lift_acc = add(lift, sizeof lift, 2, 5126, "VEC3");

  const json gltf = {
      {"asset", {{"version", "2.0"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0, 1, 3}}}}},
      {"nodes",
       {{{"name", "body"}, {"mesh", 0}, {"skin", 0}},
        {{"name", "root_bone"}, {"children", {2}}},
        {{"name", "tip_bone"}, {"translation", {0, 1, 0}}},
        {{"name", "plate"}, {"mesh", 1}}}},
      {"meshes",
       {{{"name", "blade"},
         {"primitives", {{{"attributes", {{"POSITION", skin_pos}, {"JOINTS_0", joint_acc}, {"WEIGHTS_0", weight_acc}}}}}}},
        {{"name", "plate"}, {"primitives", {{{"attributes", {{"POSITION", plate_pos}}}}}}}}},
      {"skins", {{{"joints", {1, 2}}, {"inverseBindMatrices", ibm_acc}}}},
      {"animations",
       {{{"name", "wave"},
         {"samplers",
          {{{"input", time_acc}, {"output", turn_acc}, {"interpolation", "LINEAR"}},
           {{"input", time_acc}, {"output", slide_acc}, {"interpolation", "LINEAR"}},
           {{"input", time_acc}, {"output", lift_acc}, {"interpolation", "LINEAR"}}}},
         {"channels",
          {{{"sampler", 0}, {"target", {{"node", 2}, {"path", "rotation"}}}},
           {{"sampler", 1}, {"target", {{"node", 1}, {"path", "translation"}}}},
           {{"sampler", 2}, {"target", {{"node", 3}, {"path", "translation"}}}}}}}}},
      {"buffers", {{{"byteLength", buf.size()}, {"uri", "data:application/octet-stream;base64," + base64(buf)}}}},
      {"bufferViews", views},
      {"accessors", accessors}};
  const fs::path file = temp_dir() / "two_bones.gltf";
  std::ofstream(file) << gltf.dump(1);
  return file;
}

// Where the two-bone file's vertices are at t seconds, in closed form.
std::vector<vec3f> two_bone_positions(double t) {
  const double th = t * M_PI / 2, c = std::cos(th), s = std::sin(th), dx = 2 * t;
  auto on_root = [&](vec3f p) { return std::array<double, 3>{p.x + dx, p.y, p.z}; };
  auto on_tip = [&](vec3f p) {
    const double x = p.x, y = p.y - 1;
    return std::array<double, 3>{c * x - s * y + dx, s * x + c * y + 1, p.z};
  };
  std::vector<vec3f> out;
  for (size_t v = 0; v < kSkinVertices.size(); ++v) {
    const auto a = on_root(kSkinVertices[v]), b = on_tip(kSkinVertices[v]);
    const double w = v < 3 ? 1.0 : v < 6 ? 0.0 : 0.5;
    out.push_back({float(w * a[0] + (1 - w) * b[0]), float(w * a[1] + (1 - w) * b[1]),
                   float(w * a[2] + (1 - w) * b[2])});
  }
  for (const vec3f& p : kPlateVertices) out.push_back({p.x, p.y, float(p.z + 3 * t)});
  return out;
}

TEST(AnimatedMesh, TwoBoneGltfMatchesClosedForm) {
  const fs::path file = write_two_bone_gltf();
  auto source = open_animated_clip({file, 4.0, 0, 0.0, 0, ""});
  const Topology& t = source->topology();
  ASSERT_EQ(t.faces.size(), 4u) << source->describe();
  ASSERT_EQ(t.num_vertices, 12u);
  ASSERT_EQ(source->num_frames(), 5u);  // 0, 0.25, ..., 1 s
  ASSERT_EQ(t.objects.size(), 2u);
  EXPECT_EQ(t.objects[0].name, "blade");
  EXPECT_EQ(t.objects[0].num_faces, 3u);
  EXPECT_EQ(t.objects[1].name, "plate");
  EXPECT_EQ(t.objects[1].first_face, 3u);
  std::vector<vec3f> got;
  for (uint32_t k = 0; k < source->num_frames(); ++k) {
    source->frame(k, got);
    const auto want = two_bone_positions(k / 4.0);
    for (size_t v = 0; v < want.size(); ++v) {
      EXPECT_NEAR(got[v].x, want[v].x, 1e-5) << "frame " << k << " vertex " << v;
      EXPECT_NEAR(got[v].y, want[v].y, 1e-5) << "frame " << k << " vertex " << v;
      EXPECT_NEAR(got[v].z, want[v].z, 1e-5) << "frame " << k << " vertex " << v;
    }
  }
  // Past the clip's end every channel holds its last key.
  auto late = open_animated_clip({file, 4.0, 3, 2.0, 0, "wave"});
  late->frame(2, got);
  const auto end = two_bone_positions(1.0);
  for (size_t v = 0; v < end.size(); ++v) EXPECT_NEAR(got[v].x, end[v].x, 1e-5) << "vertex " << v;
  fs::remove_all(file.parent_path());
}

// The reference: assimp's raw scene walked in double precision, written apart from the
// loader (own quaternion, slerp and key search).
struct M4 {
  double m[4][4];
};
M4 mul(const M4& a, const M4& b) {
  M4 c{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) c.m[i][j] += a.m[i][k] * b.m[k][j];
  return c;
}
M4 from(const aiMatrix4x4& a) {
  M4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r.m[i][j] = a[i][j];
  return r;
}
std::array<double, 3> apply(const M4& a, const aiVector3D& p) {
  std::array<double, 3> r;
  for (int i = 0; i < 3; ++i) r[i] = a.m[i][0] * p.x + a.m[i][1] * p.y + a.m[i][2] * p.z + a.m[i][3];
  return r;
}
struct Q {
  double w, x, y, z;
};
Q slerp(Q a, Q b, double f) {
  double d = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (d < 0) d = -d, b = {-b.w, -b.x, -b.y, -b.z};
  double ka = 1 - f, kb = f;
  if (d < 0.9999) {
    const double th = std::acos(d);
    ka = std::sin(ka * th) / std::sin(th), kb = std::sin(kb * th) / std::sin(th);
  }
  Q q{ka * a.w + kb * b.w, ka * a.x + kb * b.x, ka * a.y + kb * b.y, ka * a.z + kb * b.z};
  const double n = std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w / n, q.x / n, q.y / n, q.z / n};
}
template <class Key, class Blend>
auto sample(const Key* keys, unsigned n, double t, Blend blend) {
  if (n == 1 || t <= keys[0].mTime) return blend(keys[0].mValue, keys[0].mValue, 0.0);
  unsigned i = 0;
  while (i + 1 < n && keys[i + 1].mTime <= t) ++i;
  if (i + 1 == n) return blend(keys[i].mValue, keys[i].mValue, 0.0);
  return blend(keys[i].mValue, keys[i + 1].mValue, (t - keys[i].mTime) / (keys[i + 1].mTime - keys[i].mTime));
}

std::vector<std::array<double, 3>> reference_positions(const aiScene* sc, const aiAnimation* an, double seconds) {
  const double ticks = seconds * (an->mTicksPerSecond > 0 ? an->mTicksPerSecond : 25.0);
  std::map<const aiNode*, M4> global;
  std::vector<const aiNode*> order;
  std::function<void(const aiNode*, const M4*)> walk = [&](const aiNode* node, const M4* parent) {
    M4 local = from(node->mTransformation);
    for (unsigned c = 0; c < an->mNumChannels; ++c) {
      const aiNodeAnim* ch = an->mChannels[c];
      if (ch->mNodeName != node->mName) continue;
      aiVector3D s0, p0;
      aiQuaternion r0;
      node->mTransformation.Decompose(s0, r0, p0);
      auto lerp = [](const aiVector3D& a, const aiVector3D& b, double f) {
        return std::array<double, 3>{a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
      };
      auto p = ch->mNumPositionKeys ? sample(ch->mPositionKeys, ch->mNumPositionKeys, ticks, lerp) : lerp(p0, p0, 0);
      auto s = ch->mNumScalingKeys ? sample(ch->mScalingKeys, ch->mNumScalingKeys, ticks, lerp) : lerp(s0, s0, 0);
      auto qs = [](const aiQuaternion& a, const aiQuaternion& b, double f) {
        return slerp({a.w, a.x, a.y, a.z}, {b.w, b.x, b.y, b.z}, f);
      };
      Q q = ch->mNumRotationKeys ? sample(ch->mRotationKeys, ch->mNumRotationKeys, ticks, qs) : qs(r0, r0, 0);
      const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z, xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z,
                   wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
      const double r[3][3] = {{1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy)},
                              {2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx)},
                              {2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)}};
      local = {};
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) local.m[i][j] = r[i][j] * s[j];
        local.m[i][3] = p[i];
      }
      local.m[3][3] = 1;
    }
    global[node] = parent ? mul(*parent, local) : local;
    order.push_back(node);
    for (unsigned c = 0; c < node->mNumChildren; ++c) walk(node->mChildren[c], &global[node]);
  };
  walk(sc->mRootNode, nullptr);
  std::vector<std::array<double, 3>> out;
  for (const aiNode* node : order)
    for (unsigned i = 0; i < node->mNumMeshes; ++i) {
      const aiMesh* m = sc->mMeshes[node->mMeshes[i]];
      std::vector<std::array<double, 3>> v(m->mNumVertices, {0, 0, 0});
      std::vector<double> w(m->mNumVertices, 0);
      for (unsigned b = 0; b < m->mNumBones; ++b) {
        const M4 skin = mul(global.at(sc->mRootNode->FindNode(m->mBones[b]->mName)), from(m->mBones[b]->mOffsetMatrix));
        for (unsigned k = 0; k < m->mBones[b]->mNumWeights; ++k) {
          const aiVertexWeight& vw = m->mBones[b]->mWeights[k];
          const auto p = apply(skin, m->mVertices[vw.mVertexId]);
          for (int c = 0; c < 3; ++c) v[vw.mVertexId][c] += vw.mWeight * p[c];
          w[vw.mVertexId] += vw.mWeight;
        }
      }
      // Per triangle corner: the loader may give corners at one place one index.
      for (unsigned f = 0; f < m->mNumFaces; ++f)
        if (m->mFaces[f].mNumIndices == 3)
          for (int c = 0; c < 3; ++c) {
            const unsigned k = m->mFaces[f].mIndices[c];
            out.push_back(w[k] > 0 ? v[k] : apply(global[node], m->mVertices[k]));
          }
    }
  return out;
}

struct ModelCase {
  std::string file;  // under /usr/share/assimp/models
  uint32_t clip;
  double fps;
};

class AnimatedModels : public testing::TestWithParam<ModelCase> {};

TEST_P(AnimatedModels, MatchesPlainReferenceEveryFrame) {
  const fs::path file = kModels / GetParam().file;
  if (!fs::exists(file)) GTEST_SKIP() << kNoModels;
  auto source = open_animated_clip({file, GetParam().fps, 0, 0.0, GetParam().clip, ""});
  Assimp::Importer importer;
  const aiScene* sc = importer.ReadFile(file.string(), aiProcess_Triangulate);
  ASSERT_TRUE(sc);
  const Topology topo = source->topology();
  std::vector<vec3f> got, first;
  double moved = 0;
  for (uint32_t k = 0; k < source->num_frames(); ++k) {
    source->frame(k, got);
    ASSERT_EQ(source->topology().faces.size(), topo.faces.size()) << "frame " << k;
    std::vector<vec3d> exact;
    source->positions(k, exact);
    ASSERT_NO_THROW(check_frame(exact, topo, file.string(), k));
    const auto want = reference_positions(sc, sc->mAnimations[GetParam().clip], k / GetParam().fps);
    ASSERT_EQ(want.size(), 3 * topo.faces.size());
    double scale = 1;
    for (const auto& p : want) scale = std::max({scale, std::abs(p[0]), std::abs(p[1]), std::abs(p[2])});
    for (size_t f = 0; f < topo.faces.size(); ++f) {
      const uint32_t corner[3] = {topo.faces[f].v0, topo.faces[f].v1, topo.faces[f].v2};
      for (int c = 0; c < 3; ++c) {
        const vec3f& p = got[corner[c]];
        const auto& q = want[3 * f + c];
        const double err = std::max({std::abs(p.x - q[0]), std::abs(p.y - q[1]), std::abs(p.z - q[2])});
        ASSERT_LE(err, 2e-5 * scale) << "frame " << k << " face " << f << " corner " << c;
      }
    }
    if (k == 0) first = got;
    for (size_t v = 0; v < got.size(); ++v)
      moved = std::max({moved, double(std::abs(got[v].x - first[v].x)), double(std::abs(got[v].y - first[v].y)),
                        double(std::abs(got[v].z - first[v].z))});
  }
  EXPECT_GT(moved, 0) << "the model does not move";
}

INSTANTIATE_TEST_SUITE_P(
    TestModels, AnimatedModels,
    testing::Values(ModelCase{"X/BCN_Epileptic.X", 0, 7.5}, ModelCase{"X/Testwuson.X", 1, 10},
ModelCase{"FBX/animation_with_skeleton.fbx", 0, 24},
                    ModelCase{"glTF2/simple_skin/simple_skin.gltf", 0, 4},
                    ModelCase{"Collada/box_nested_animation.dae", 0, 12},
                    ModelCase{"Collada/anims_with_full_rotations_between_keys.DAE", 0, 5}),
    [](const testing::TestParamInfo<ModelCase>& i) {
      return param_name(fs::path(i.param.file).stem().string());
    });

TEST(AnimatedMesh, MorphCubeBlendsItsTargets) {
  const fs::path file = kModels / "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf";
  if (!fs::exists(file)) GTEST_SKIP() << kNoModels;
  auto source = open_animated_clip({file, 10, 0, 0.0, 0, ""});
  Assimp::Importer importer;
  const aiScene* sc = importer.ReadFile(file.string(), aiProcess_Triangulate);
  ASSERT_TRUE(sc && sc->mNumMeshes == 1 && sc->mMeshes[0]->mNumAnimMeshes == 2);
  const aiMesh* m = sc->mMeshes[0];
  const aiMeshMorphAnim* ch = sc->mAnimations[0]->mMorphMeshChannels[0];
  std::vector<vec3f> got;
  double moved = 0;
  for (uint32_t k = 0; k < source->num_frames(); k += 3) {
    source->frame(k, got);
    // Weights at this time by linear search and blend; the cube is the root node.
    const double t = k / 10.0 * sc->mAnimations[0]->mTicksPerSecond;
    unsigned i = 0;
    while (i + 1 < ch->mNumKeys && ch->mKeys[i + 1].mTime <= t) ++i;
    const double f = i + 1 < ch->mNumKeys && t > ch->mKeys[0].mTime
                         ? (t - ch->mKeys[i].mTime) / (ch->mKeys[i + 1].mTime - ch->mKeys[i].mTime) : 0;
    double w[2] = {0, 0};
    for (unsigned j = 0; j < ch->mKeys[i].mNumValuesAndWeights; ++j)
      w[ch->mKeys[i].mValues[j]] += (1 - f) * ch->mKeys[i].mWeights[j];
    if (f > 0)
      for (unsigned j = 0; j < ch->mKeys[i + 1].mNumValuesAndWeights; ++j)
        w[ch->mKeys[i + 1].mValues[j]] += f * ch->mKeys[i + 1].mWeights[j];
    for (unsigned face = 0; face < m->mNumFaces; ++face) {
      const Tri& tri = source->topology().faces[face];
      const uint32_t ours[3] = {tri.v0, tri.v1, tri.v2};
      for (int c = 0; c < 3; ++c) {
        const unsigned v = m->mFaces[face].mIndices[c];
        double p[3] = {m->mVertices[v].x, m->mVertices[v].y, m->mVertices[v].z};
        for (int a = 0; a < 2; ++a) {
          const aiVector3D& q = m->mAnimMeshes[a]->mVertices[v];
          p[0] += w[a] * (q.x - m->mVertices[v].x);
          p[1] += w[a] * (q.y - m->mVertices[v].y);
          p[2] += w[a] * (q.z - m->mVertices[v].z);
        }
        const aiVector3D world = sc->mRootNode->mTransformation * aiVector3D(float(p[0]), float(p[1]), float(p[2]));
        const vec3f& g = got[ours[c]];
        EXPECT_NEAR(g.x, world.x, 1e-4) << "frame " << k << " face " << face << " corner " << c;
        EXPECT_NEAR(g.y, world.y, 1e-4) << "frame " << k << " face " << face << " corner " << c;
        EXPECT_NEAR(g.z, world.z, 1e-4) << "frame " << k << " face " << face << " corner " << c;
        moved = std::max(moved, std::abs(double(g.y) - m->mVertices[v].y));
      }
    }
  }
  EXPECT_GT(moved, 0.01) << "the morph weights never move the cube";
}

TEST(AnimatedMesh, BcnJumpSceneLoadsAndMoves) {
  if (!fs::exists(kModels / "X/BCN_Epileptic.X")) GTEST_SKIP() << kNoModels;
  const Scene s = open_scene("bcn-jump", default_scenes_dir());
  const Topology& t = s.source->topology();
  EXPECT_EQ(t.faces.size(), 5126u);
  EXPECT_EQ(t.objects.size(), 3u);
  EXPECT_EQ(s.source->num_frames(), 100u);
  // The file gives each face its own three vertices; welding finds the shared corners.
  EXPECT_LT(t.num_vertices, 3u * 5126u / 2);
  std::vector<vec3f> a, b;
  s.source->frame(0, a);
  s.source->frame(50, b);
  double moved = 0;
  for (size_t v = 0; v < a.size(); ++v) moved = std::max(moved, double(std::abs(a[v].y - b[v].y)));
  EXPECT_GT(moved, 0.01) << "the jump does not move the body";
}

// Descriptors around the two-bone file, written next to it.
struct Descriptor {
  fs::path dir = temp_dir();
  fs::path write(const json& j) {
    const fs::path f = dir / "scene.json";
    std::ofstream(f) << j.dump();
    return f;
  }
  ~Descriptor() { fs::remove_all(dir); }
};

TEST(AnimatedMesh, DescriptorWithObjectQueries) {
  Descriptor d;
  write_two_bone_gltf();
  const fs::path f = d.write({{"animation", {{"file", "two_bones.gltf"}, {"fps", 8}, {"frames", 3}, {"clip", "wave"}}},
                              {"queries", {{"inter", json::array({json::array({"blade", "plate"})})}}}});
  const Scene s = open_scene(f.string(), d.dir);
  EXPECT_EQ(s.source->num_frames(), 3u);
  EXPECT_TRUE(s.source->topology().queries.declared);
  ASSERT_EQ(s.source->topology().queries.inter.size(), 1u);
  EXPECT_EQ(s.source->topology().queries.inter[0], std::make_pair(0u, 1u));
  std::vector<vec3f> v;
  s.source->frame(2, v);
  EXPECT_NEAR(v[9].z, 3 * 2 / 8.0, 1e-5);
}

TEST(AnimatedMesh, ErrorsNameTheFileAndField) {
  Descriptor d;
  write_two_bone_gltf();
  auto open = [&](const json& j) { return error_of([&] { open_scene(d.write(j).string(), d.dir); }); };
  const json ok = {{"file", "two_bones.gltf"}};
  auto with = [&](const char* key, json value) {
    json a = ok;
    a[key] = value;
    return json{{"animation", a}};
  };
  EXPECT_NE(open(with("fps", 0)).find("/animation/fps"), std::string::npos);
  EXPECT_NE(open(with("frames", -2)).find("/animation/frames"), std::string::npos);
  EXPECT_NE(open(with("start", "soon")).find("/animation/start"), std::string::npos);
  EXPECT_NE(open(with("clip", 4)).find("clip 4 out of range (clips: 0 'wave')"), std::string::npos);
  EXPECT_NE(open(with("clip", "run")).find("no clip named 'run'"), std::string::npos);
  EXPECT_NE(open(with("speed", 2)).find("/animation/speed: unknown key"), std::string::npos);
  EXPECT_NE(open(with("file", 7)).find("/animation/file"), std::string::npos);
  EXPECT_NE(open({{"animation", ok}, {"generator", "flag"}}).find("exactly one of"), std::string::npos);
  const std::string missing = open(with("file", "nothing.gltf"));
  EXPECT_NE(missing.find((d.dir / "nothing.gltf").string() + ": no such file"), std::string::npos) << missing;
  const std::string model = open(with("file", "/usr/share/assimp/models/X/no_such_model.X"));
  EXPECT_NE(model.find("no_such_model.X: no such file (it ships with the Debian package assimp-testmodels: run "
                       "scripts/install-deps.sh --scenes)"),
            std::string::npos)
      << model;
  std::ofstream(d.dir / "broken.gltf") << "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 3}";
  const std::string broken = open(with("file", "broken.gltf"));
  EXPECT_NE(broken.find("broken.gltf: cannot read"), std::string::npos) << broken;
  EXPECT_NE(error_of([&] { open_animated_clip({d.dir / "absent.glb", 30, 0, 0, 0, ""}); }).find("absent.glb: no such file"),
            std::string::npos);
}

// A test model whose skin names a bone the file has no node for.
TEST(AnimatedMesh, ModelBoneWithoutNodeIsAnError) {
  const fs::path file = kModels / "X/anim_test.x";
  if (!fs::exists(file)) GTEST_SKIP() << kNoModels;
  EXPECT_NE(error_of([&] { open_animated_clip({file, 30, 0, 0, 0, ""}); })
                .find("anim_test.x: mesh 'pCylinder1' bone 'joint3': no node of that name"),
            std::string::npos);
}

}  // namespace
}  // namespace cdb::test
