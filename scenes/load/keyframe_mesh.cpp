#include "scenes/load/keyframe_mesh.h"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <tuple>

#include "cdbench/core/error.h"
#include "cdbench/core/float_bits.h"
#include "scenes/load/input_files.h"

namespace cdb {
namespace {

// One import flattened: node hierarchy applied, meshes in node depth-first order.
struct FlatKeyframe {
  std::vector<Tri> faces;  // indices into positions, before welding
  std::vector<aiVector3D> positions;
  std::vector<SceneObject> objects;
  std::vector<uint32_t> vertex_object;  // per position, its object (welding stays within one)
};

void flatten(const aiScene* scene, const aiNode* node, const aiMatrix4x4& parent, const std::string& file_stem,
             FlatKeyframe& out, std::set<std::string>& names) {
  const aiMatrix4x4 global = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[node->mMeshes[i]];
    const uint32_t base = uint32_t(out.positions.size()), first_face = uint32_t(out.faces.size());
    for (unsigned f = 0; f < mesh->mNumFaces; ++f)
      if (mesh->mFaces[f].mNumIndices == 3)  // points and lines carry no triangle
        out.faces.push_back({base + mesh->mFaces[f].mIndices[0], base + mesh->mFaces[f].mIndices[1],
                             base + mesh->mFaces[f].mIndices[2]});
    const uint32_t num_faces = uint32_t(out.faces.size()) - first_face;
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      out.positions.push_back(global * mesh->mVertices[v]);
      out.vertex_object.push_back(uint32_t(out.objects.size()));
    }
    // Names must be unique for a descriptor's queries to name them; MD2 names neither mesh
    // nor node, so the file names its one mesh.
    const std::string stem = mesh->mName.length ? mesh->mName.C_Str()
                             : node->mName.length ? node->mName.C_Str()
                                                  : file_stem;
    std::string name = stem;
    for (int dup = 2; !names.insert(name).second; ++dup) name = stem + "#" + std::to_string(dup);
    out.objects.push_back({name, first_face, num_faces, false});
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    flatten(scene, node->mChildren[c], global, file_stem, out, names);
}

FlatKeyframe import_keyframe(const std::string& file, uint32_t keyframe) {
  Assimp::Importer importer;
  importer.SetPropertyInteger(AI_CONFIG_IMPORT_GLOBAL_KEYFRAME, int(keyframe));
  // Triangulate only: no vertex joining or degenerate removal, so every face of the file is
  // a triangle of the scene.
  const aiScene* scene = importer.ReadFile(file, aiProcess_Triangulate);
  if (!scene) fail(file + ": keyframe " + std::to_string(keyframe) + ": cannot read: " + importer.GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE)
    fail(file + ": keyframe " + std::to_string(keyframe) + ": incomplete scene (no meshes)");
  FlatKeyframe flat;
  std::set<std::string> names;
  flatten(scene, scene->mRootNode, aiMatrix4x4(), std::filesystem::path(file).stem().string(), flat, names);
  if (flat.faces.empty()) fail(file + ": keyframe " + std::to_string(keyframe) + ": no triangles");
  return flat;
}

class KeyframeMesh final : public FrameSource {
 public:
  explicit KeyframeMesh(const KeyframeOptions& o) : options_(o), file_(o.file.string()) {
    if (!std::filesystem::is_regular_file(o.file)) fail(file_ + ": no such file");
    if (o.subframes == 0) fail(file_ + ": subframes must be at least 1");
    const uint32_t in_header = keyframes_in_header(o.file);
    num_frames_ = o.frames;
    if (in_header) {
      if (o.first >= in_header)
        fail(file_ + ": first keyframe " + std::to_string(o.first) + " out of range (the file has " +
             std::to_string(in_header) + " keyframes)");
      if (num_frames_ == 0) num_frames_ = (in_header - 1 - o.first) * o.subframes + 1;
    } else if (num_frames_ == 0) {
      fail(file_ + ": the number of frames must be given: the keyframe count of this format is not known");
    }
    // The last frame's keyframe, and the next one when the last frame blends towards it.
    const uint64_t last = o.first + uint64_t(num_frames_ - 1) / o.subframes + ((num_frames_ - 1) % o.subframes != 0);
    num_keyframes_ = uint32_t(last - o.first + 1);
    if (in_header && last >= in_header)
      fail(file_ + ": keyframes " + std::to_string(o.first) + ".." + std::to_string(last) + " asked for, the file has " +
           std::to_string(in_header) + " (0.." + std::to_string(in_header - 1) + ")");
    const FlatKeyframe first = import_keyframe(file_, o.first);
    raw_faces_ = first.faces;
    num_raw_vertices_ = first.positions.size();
    topology_.objects = first.objects;
    // Partition refinement: vertices of one object start in one class, and each keyframe
    // splits classes by position bits. What is left together is the same in every keyframe,
    // so merging it is exact.
    std::vector<uint32_t> cls = first.vertex_object;
    for (uint32_t k = 0; k < num_keyframes_; ++k) {
      const FlatKeyframe f = k == 0 ? first : import_keyframe(file_, o.first + k);
      check_topology(f, o.first + k);
      std::map<std::tuple<uint32_t, uint32_t, uint32_t, uint32_t>, uint32_t> refined;
      for (size_t v = 0; v < cls.size(); ++v)
        cls[v] = refined.emplace(std::make_tuple(cls[v], float_bits(f.positions[v].x), float_bits(f.positions[v].y),
                                                 float_bits(f.positions[v].z)),
                                 uint32_t(refined.size()))
                     .first->second;
    }
    weld_ = cls;
    topology_.num_vertices = num_raw_vertices_ ? *std::max_element(weld_.begin(), weld_.end()) + 1 : 0;
    for (const Tri& t : raw_faces_) topology_.faces.push_back({weld_[t.v0], weld_[t.v1], weld_[t.v2]});
  }

  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return num_frames_; }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= num_frames_)
      fail(file_ + ": frame " + std::to_string(k) + " out of range (" + std::to_string(num_frames_) + " frames)");
    const uint32_t key = options_.first + k / options_.subframes, step = k % options_.subframes;
    const FlatKeyframe a = import_keyframe(file_, key);
    check_topology(a, key);
    out.assign(topology_.num_vertices, vec3d{0, 0, 0});
    if (step == 0) {
      for (size_t v = 0; v < a.positions.size(); ++v) out[weld_[v]] = {a.positions[v].x, a.positions[v].y, a.positions[v].z};
    } else {
      const FlatKeyframe b = import_keyframe(file_, key + 1);
      check_topology(b, key + 1);
      const double w = double(step) / options_.subframes;
      auto blend = [w](double p, double q) { return p + w * (q - p); };
      for (size_t v = 0; v < a.positions.size(); ++v)
        out[weld_[v]] = {blend(a.positions[v].x, b.positions[v].x), blend(a.positions[v].y, b.positions[v].y),
                         blend(a.positions[v].z, b.positions[v].z)};
    }
    check_frame(out, topology_, file_ + " (keyframe " + std::to_string(key) + ")", k);
  }

  std::string describe() const override {
    return "keyframe mesh " + file_ + ": " + std::to_string(topology_.faces.size()) + " triangles, keyframes " +
           std::to_string(options_.first) + ".." + std::to_string(options_.first + num_keyframes_ - 1) + ", " +
           std::to_string(options_.subframes) + " frames per keyframe (" + std::to_string(num_frames_) + " frames)";
  }

 private:
  void check_topology(const FlatKeyframe& f, uint32_t keyframe) const {
    const std::string at = file_ + ": keyframe " + std::to_string(keyframe) + " has ";
    const std::string ref = ", keyframe " + std::to_string(options_.first) + " has ";
    if (f.positions.size() != num_raw_vertices_)
      fail(at + std::to_string(f.positions.size()) + " vertices" + ref + std::to_string(num_raw_vertices_) +
           " (topology must stay fixed)");
    if (f.faces.size() != raw_faces_.size())
      fail(at + std::to_string(f.faces.size()) + " triangles" + ref + std::to_string(raw_faces_.size()) +
           " (topology must stay fixed)");
    for (size_t t = 0; t < f.faces.size(); ++t)
      if (f.faces[t].v0 != raw_faces_[t].v0 || f.faces[t].v1 != raw_faces_[t].v1 || f.faces[t].v2 != raw_faces_[t].v2)
        fail(file_ + ": keyframe " + std::to_string(keyframe) + ", triangle " + std::to_string(t) +
             ": other corners than in keyframe " + std::to_string(options_.first) + " (topology must stay fixed)");
  }

  KeyframeOptions options_;
  std::string file_;
  uint32_t num_frames_ = 0, num_keyframes_ = 0;
  std::vector<Tri> raw_faces_;
  size_t num_raw_vertices_ = 0;
  std::vector<uint32_t> weld_;  // per imported vertex, its scene vertex
  Topology topology_;
};

}  // namespace

uint32_t keyframes_in_header(const std::filesystem::path& file) {
  // MD2: "IDP2", then 32-bit little-endian fields; the frame count is the 11th. MD3: "IDP3",
  // version, a 64-byte name, flags, then the frame count.
  std::ifstream in(file, std::ios::binary);
  char header[80] = {};
  in.read(header, sizeof header);
  const auto got = in.gcount();
  if (got >= 4 && std::memcmp(header, "IDP2", 4) == 0) {
    if (got < 44) fail(file.string() + ": MD2 header cut short");
    return uint32_t(little_endian(header + 40, 4));
  }
  if (got >= 4 && std::memcmp(header, "IDP3", 4) == 0) {
    if (got < 80) fail(file.string() + ": MD3 header cut short");
    return uint32_t(little_endian(header + 76, 4));
  }
  return 0;
}

std::unique_ptr<FrameSource> open_keyframe_mesh(const KeyframeOptions& options) {
  return std::make_unique<KeyframeMesh>(options);
}

}  // namespace cdb
