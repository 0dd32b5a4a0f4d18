#include "scenes/load/animated_mesh.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <unordered_map>

#include "cdbench/core/error.h"
#include "cdbench/core/float_bits.h"
#include "scenes/load/quaternion.h"

namespace cdb {
namespace {

// assimp's own animation evaluator assumes this rate when a file does not give one.
constexpr double kDefaultTicksPerSecond = 25.0;

// Index of the last key at or before `t`, and how far `t` is towards the next one (0..1).
// Before the first key and after the last the channel holds its end value.
template <class Key>
std::pair<unsigned, double> bracket(const Key* keys, unsigned n, double t) {
  if (n == 1 || t <= keys[0].mTime) return {0, 0.0};
  if (t >= keys[n - 1].mTime) return {n - 1, 0.0};
  const Key* next = std::upper_bound(keys, keys + n, t, [](double x, const Key& k) { return x < k.mTime; });
  const unsigned i = unsigned(next - keys) - 1;
  const double span = keys[i + 1].mTime - keys[i].mTime;
  return {i, span > 0 ? (t - keys[i].mTime) / span : 0.0};
}

aiVector3D lerp_key(const aiVectorKey* keys, unsigned n, double t) {
  const auto [i, f] = bracket(keys, n, t);
  if (f == 0.0) return keys[i].mValue;
  return keys[i].mValue + ai_real(f) * (keys[i + 1].mValue - keys[i].mValue);
}

aiQuaternion slerp_key(const aiQuatKey* keys, unsigned n, double t) {
  const auto [i, f] = bracket(keys, n, t);
  const aiQuaternion &a = keys[i].mValue, &b = keys[f == 0.0 ? i : i + 1].mValue;
  const Quat q = slerp({a.w, a.x, a.y, a.z}, {b.w, b.x, b.y, b.z}, f);
  return aiQuaternion(ai_real(q.w), ai_real(q.x), ai_real(q.y), ai_real(q.z));
}

// A mesh placed in the scene by a node: its vertex v is frame vertex first_vertex + weld[v].
struct Instance {
  const aiMesh* mesh;
  uint32_t node;                      // index into AnimatedMesh::nodes_
  uint32_t first_vertex;
  std::vector<uint32_t> weld;
  std::vector<uint32_t> bone_nodes;   // per mesh bone, the node that drives it
  const aiMeshMorphAnim* morph = nullptr;
};

class AnimatedMesh final : public AnimatedClip {
 public:
  explicit AnimatedMesh(const AnimationOptions& o) : options_(o), file_(o.file.string()) {
    if (!std::filesystem::is_regular_file(o.file)) fail(file_ + ": no such file");
    if (!(o.fps > 0) || !std::isfinite(o.fps)) fail(file_ + ": fps must be positive");
    if (!(o.start >= 0) || !std::isfinite(o.start)) fail(file_ + ": start must be >= 0 seconds");
    // Triangulate only: no vertex joining or degenerate removal, so every face of the file
    // stays a triangle of the scene (a pair is defined on the input's faces).
    scene_ = importer_.ReadFile(file_, aiProcess_Triangulate);
    if (!scene_) fail(file_ + ": cannot read: " + importer_.GetErrorString());
    if (scene_->mFlags & AI_SCENE_FLAGS_INCOMPLETE) fail(file_ + ": incomplete scene (no meshes)");
    pick_clip();
    collect_nodes(scene_->mRootNode, UINT32_MAX);
    collect_instances();
    if (anim_->mTicksPerSecond > 0) ticks_per_second_ = anim_->mTicksPerSecond;
    num_frames_ = o.frames;
    if (num_frames_ == 0) {
      if (o.start > clip_seconds())
        fail(file_ + ": start " + std::to_string(o.start) + " s is past the end of clip '" + clip_name_ + "' (" +
             std::to_string(clip_seconds()) + " s)");
      num_frames_ = uint32_t(std::floor((clip_seconds() - o.start) * o.fps + 1e-9)) + 1;
    }
  }

  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return num_frames_; }

  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= num_frames_)
      fail(file_ + ": frame " + std::to_string(k) + " out of range (" + std::to_string(num_frames_) + " frames)");
    std::vector<vec3f> f;
    evaluate(options_.start + k / options_.fps, f);
    widen_to_double(f, out);
    check_frame(out, topology_, file_, k);
  }

  void positions_at(double seconds, std::vector<vec3f>& out) const override {
    evaluate(seconds, out);
    std::vector<vec3d> d;
    widen_to_double(out, d);
    check_frame(d, topology_, file_ + " at " + std::to_string(seconds) + " s", 0);
  }

  double clip_seconds() const override { return anim_->mDuration / ticks_per_second_; }

  std::string describe() const override {
    return "animated mesh " + file_ + ", clip '" + clip_name_ + "': " + std::to_string(topology_.faces.size()) +
           " triangles, " + std::to_string(instances_.size()) + " meshes, " + std::to_string(num_frames_) +
           " frames at " + std::to_string(options_.fps) + " fps from " + std::to_string(options_.start) + " s";
  }

 private:
  void evaluate(double seconds, std::vector<vec3f>& out) const {
    const double ticks = seconds * ticks_per_second_;
    const std::vector<aiMatrix4x4> global = global_transforms(ticks);
    out.assign(topology_.num_vertices, vec3f{0, 0, 0});
    std::vector<aiVector3D> bind;
    for (const Instance& in : instances_) {
      morphed_bind_pose(in, ticks, bind);
      const aiMesh* m = in.mesh;
      if (m->mNumBones == 0) {
        for (unsigned v = 0; v < m->mNumVertices; ++v) store(out, in.first_vertex + in.weld[v], global[in.node] * bind[v]);
        continue;
      }
      // Linear blend skinning: v = sum_b w_b (Global(bone node) * offset_b) v_bind.
      std::vector<aiVector3D> skinned(m->mNumVertices, aiVector3D(0, 0, 0));
      std::vector<ai_real> weight(m->mNumVertices, 0);
      for (unsigned b = 0; b < m->mNumBones; ++b) {
        const aiBone* bone = m->mBones[b];
        const aiMatrix4x4 skin = global[in.bone_nodes[b]] * bone->mOffsetMatrix;
        for (unsigned w = 0; w < bone->mNumWeights; ++w) {
          const aiVertexWeight& vw = bone->mWeights[w];
          skinned[vw.mVertexId] += vw.mWeight * (skin * bind[vw.mVertexId]);
          weight[vw.mVertexId] += vw.mWeight;
        }
      }
      // A vertex no bone holds would collapse to the origin; it follows its mesh's node.
      for (unsigned v = 0; v < m->mNumVertices; ++v)
        store(out, in.first_vertex + in.weld[v], weight[v] > 0 ? skinned[v] : global[in.node] * bind[v]);
    }
  }

  void pick_clip() {
    if (scene_->mNumAnimations == 0) fail(file_ + ": no animation in this file");
    std::string names;
    for (unsigned a = 0; a < scene_->mNumAnimations; ++a)
      names += (names.empty() ? "" : ", ") + std::to_string(a) + " '" +
               std::string(scene_->mAnimations[a]->mName.C_Str()) + "'";
    if (!options_.clip_name.empty()) {
      for (unsigned a = 0; a < scene_->mNumAnimations && !anim_; ++a)
        if (options_.clip_name == scene_->mAnimations[a]->mName.C_Str()) anim_ = scene_->mAnimations[a];
      if (!anim_) fail(file_ + ": no clip named '" + options_.clip_name + "' (clips: " + names + ")");
    } else {
      if (options_.clip >= scene_->mNumAnimations)
        fail(file_ + ": clip " + std::to_string(options_.clip) + " out of range (clips: " + names + ")");
      anim_ = scene_->mAnimations[options_.clip];
    }
    clip_name_ = anim_->mName.C_Str();
  }

  // Depth-first, parents before children, so global transforms are one pass.
  void collect_nodes(const aiNode* node, uint32_t parent) {
    const uint32_t index = uint32_t(nodes_.size());
    nodes_.push_back(node);
    parents_.push_back(parent);
    node_index_.emplace(node->mName.C_Str(), index);  // the first of equal names, as assimp's FindNode
    channels_.push_back(nullptr);
    for (unsigned c = 0; c < node->mNumChildren; ++c) collect_nodes(node->mChildren[c], index);
  }

  void collect_instances() {
    for (unsigned c = 0; c < anim_->mNumChannels; ++c) {
      const auto it = node_index_.find(anim_->mChannels[c]->mNodeName.C_Str());
      // A channel for a node the scene lacks moves nothing.
      if (it != node_index_.end()) channels_[it->second] = anim_->mChannels[c];
    }
    std::set<std::string> used_names;
    for (uint32_t n = 0; n < nodes_.size(); ++n) {
      const aiNode* node = nodes_[n];
      for (unsigned i = 0; i < node->mNumMeshes; ++i) {
        const aiMesh* mesh = scene_->mMeshes[node->mMeshes[i]];
        const uint32_t first_face = uint32_t(topology_.faces.size());
        const uint32_t base = topology_.num_vertices;
        for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
          const aiFace& face = mesh->mFaces[f];
          if (face.mNumIndices != 3) continue;  // points and lines carry no triangle
          topology_.faces.push_back({base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        }
        const uint32_t num_faces = uint32_t(topology_.faces.size()) - first_face;
        if (num_faces == 0) continue;
        Instance in{mesh, n, base, weld_map(mesh), {}, find_morph(mesh, node)};
        const uint32_t welded = in.weld.empty() ? 0 : *std::max_element(in.weld.begin(), in.weld.end()) + 1;
        for (uint32_t f = first_face; f < topology_.faces.size(); ++f) {
          Tri& t = topology_.faces[f];
          t = {base + in.weld[t.v0 - base], base + in.weld[t.v1 - base], base + in.weld[t.v2 - base]};
        }
        for (unsigned b = 0; b < mesh->mNumBones; ++b) {
          const std::string bone = mesh->mBones[b]->mName.C_Str();
          const auto it = node_index_.find(bone);
          if (it == node_index_.end())
            fail(file_ + ": mesh '" + mesh->mName.C_Str() + "' bone '" + bone + "': no node of that name");
          in.bone_nodes.push_back(it->second);
        }
        topology_.num_vertices += welded;
        instances_.push_back(std::move(in));
        // Names must be unique for the descriptor's queries to name them.
        const std::string stem = mesh->mName.length ? mesh->mName.C_Str() : node->mName.C_Str();
        std::string name = stem.empty() ? "mesh" + std::to_string(node->mMeshes[i]) : stem;
        for (int dup = 2; !used_names.insert(name).second; ++dup) name = stem + "#" + std::to_string(dup);
        topology_.objects.push_back({name, first_face, num_faces, false});
      }
    }
    if (topology_.faces.empty()) fail(file_ + ": no triangles in this file");
  }

  // Files that split vertices per face (X, FBX) would hide which triangles share a corner
  // from co-vertex filtering. Vertices of one mesh with the same bind position, morph
  // target positions and bone weights take the same index: they are computed by the same
  // operations in every frame, so the merge is exact and no face changes.
  std::vector<uint32_t> weld_map(const aiMesh* mesh) const {
    std::vector<std::vector<uint32_t>> key(mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      key[v] = {float_bits(p.x), float_bits(p.y), float_bits(p.z)};
      for (unsigned t = 0; t < mesh->mNumAnimMeshes; ++t)
        if (const aiAnimMesh* target = mesh->mAnimMeshes[t]; target->mVertices && v < target->mNumVertices)
          key[v].insert(key[v].end(), {float_bits(target->mVertices[v].x), float_bits(target->mVertices[v].y),
                                       float_bits(target->mVertices[v].z)});
    }
    // Bones in mesh order, the order skinning sums them in.
    for (unsigned b = 0; b < mesh->mNumBones; ++b)
      for (unsigned w = 0; w < mesh->mBones[b]->mNumWeights; ++w) {
        const aiVertexWeight& vw = mesh->mBones[b]->mWeights[w];
        if (vw.mVertexId >= mesh->mNumVertices)
          fail(file_ + ": mesh '" + mesh->mName.C_Str() + "' bone '" + mesh->mBones[b]->mName.C_Str() +
               "': weight for vertex " + std::to_string(vw.mVertexId) + " of " + std::to_string(mesh->mNumVertices));
        key[vw.mVertexId].insert(key[vw.mVertexId].end(), {~0u, b, float_bits(vw.mWeight)});
      }
    std::map<std::vector<uint32_t>, uint32_t> first;
    std::vector<uint32_t> weld(mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v)
      weld[v] = first.emplace(std::move(key[v]), uint32_t(first.size())).first->second;
    return weld;
  }

  // Morph channels name the mesh or its node; glTF files from assimp add "*<target>".
  const aiMeshMorphAnim* find_morph(const aiMesh* mesh, const aiNode* node) const {
    if (mesh->mNumAnimMeshes == 0) return nullptr;
    for (unsigned c = 0; c < anim_->mNumMorphMeshChannels; ++c) {
      std::string name = anim_->mMorphMeshChannels[c]->mName.C_Str();
      name = name.substr(0, name.find('*'));
      if (name == mesh->mName.C_Str() || name == node->mName.C_Str()) return anim_->mMorphMeshChannels[c];
    }
    return nullptr;
  }

  std::vector<aiMatrix4x4> global_transforms(double ticks) const {
    std::vector<aiMatrix4x4> global(nodes_.size());
    for (uint32_t n = 0; n < nodes_.size(); ++n) {
      aiMatrix4x4 local = nodes_[n]->mTransformation;
      if (const aiNodeAnim* ch = channels_[n]) {
        // A channel replaces the node's local transform by T * R * S; a component without
        // keys keeps the node's own.
        aiVector3D scaling, position;
        aiQuaternion rotation;
        local.Decompose(scaling, rotation, position);
        if (ch->mNumPositionKeys) position = lerp_key(ch->mPositionKeys, ch->mNumPositionKeys, ticks);
        if (ch->mNumRotationKeys) rotation = slerp_key(ch->mRotationKeys, ch->mNumRotationKeys, ticks);
        if (ch->mNumScalingKeys) scaling = lerp_key(ch->mScalingKeys, ch->mNumScalingKeys, ticks);
        aiMatrix4x4 t, s;
        aiMatrix4x4::Translation(position, t);
        aiMatrix4x4::Scaling(scaling, s);
        local = t * aiMatrix4x4(rotation.GetMatrix()) * s;
      }
      global[n] = parents_[n] == UINT32_MAX ? local : global[parents_[n]] * local;
    }
    return global;
  }

  // Bind pose with morph targets blended in: v = v_base + sum_i w_i (target_i - v_base)
  // (assimp stores targets as absolute positions). Without a morph channel the targets'
  // own weights apply.
  void morphed_bind_pose(const Instance& in, double ticks, std::vector<aiVector3D>& out) const {
    const aiMesh* m = in.mesh;
    out.assign(m->mVertices, m->mVertices + m->mNumVertices);
    if (m->mNumAnimMeshes == 0) return;
    std::vector<double> w(m->mNumAnimMeshes, 0.0);
    if (in.morph) {
      const auto [i, f] = bracket(in.morph->mKeys, in.morph->mNumKeys, ticks);
      const auto add = [&](const aiMeshMorphKey& key, double share) {
        for (unsigned j = 0; j < key.mNumValuesAndWeights; ++j)
          if (key.mValues[j] < w.size()) w[key.mValues[j]] += share * key.mWeights[j];
      };
      add(in.morph->mKeys[i], 1 - f);
      if (f > 0) add(in.morph->mKeys[i + 1], f);
    } else {
      for (unsigned t = 0; t < m->mNumAnimMeshes; ++t) w[t] = m->mAnimMeshes[t]->mWeight;
    }
    for (unsigned t = 0; t < m->mNumAnimMeshes; ++t) {
      const aiAnimMesh* target = m->mAnimMeshes[t];
      if (w[t] == 0 || !target->mVertices) continue;
      if (target->mNumVertices != m->mNumVertices)
        fail(file_ + ": mesh '" + m->mName.C_Str() + "' morph target " + std::to_string(t) + " has " +
             std::to_string(target->mNumVertices) + " vertices, the mesh " + std::to_string(m->mNumVertices));
      for (unsigned v = 0; v < m->mNumVertices; ++v)
        out[v] += ai_real(w[t]) * (target->mVertices[v] - m->mVertices[v]);
    }
  }

  static void store(std::vector<vec3f>& out, uint32_t i, const aiVector3D& p) { out[i] = {p.x, p.y, p.z}; }

  AnimationOptions options_;
  std::string file_;
  Assimp::Importer importer_;  // owns scene_
  const aiScene* scene_ = nullptr;
  const aiAnimation* anim_ = nullptr;
  std::string clip_name_;
  double ticks_per_second_ = kDefaultTicksPerSecond;
  uint32_t num_frames_ = 0;
  std::vector<const aiNode*> nodes_;
  std::vector<uint32_t> parents_;
  std::vector<const aiNodeAnim*> channels_;
  std::unordered_map<std::string, uint32_t> node_index_;
  std::vector<Instance> instances_;
  Topology topology_;
};

}  // namespace

std::unique_ptr<AnimatedClip> open_animated_clip(const AnimationOptions& options) {
  return std::make_unique<AnimatedMesh>(options);
}

}  // namespace cdb
