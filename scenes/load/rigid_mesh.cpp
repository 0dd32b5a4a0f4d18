#include "scenes/load/rigid_mesh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <map>
#include <tuple>

#include "cdbench/core/error.h"
#include "cdbench/geometry/position_rounding.h"
#include "scenes/load/keyframe_mesh.h"
#include "scenes/load/input_files.h"
#include "scenes/load/obj_sequence.h"
#include "scenes/load/quaternion.h"

namespace cdb {
namespace {

using scene::dvec3;
using scene::Pose;

Quat axis_angle(dvec3 axis, double angle, const std::string& where) {
  const double len = scene::length(axis);
  if (!(len > 0)) fail(where + ": the rotation axis is zero");
  const double s = std::sin(angle / 2) / len;
  return {std::cos(angle / 2), axis.x * s, axis.y * s, axis.z * s};
}

Pose from_quat(const Quat& q) {
  Pose p;
  const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z, xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z,
               wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  p.r[0][0] = 1 - 2 * (yy + zz), p.r[0][1] = 2 * (xy - wz), p.r[0][2] = 2 * (xz + wy);
  p.r[1][0] = 2 * (xy + wz), p.r[1][1] = 1 - 2 * (xx + zz), p.r[1][2] = 2 * (yz - wx);
  p.r[2][0] = 2 * (xz - wy), p.r[2][1] = 2 * (yz + wx), p.r[2][2] = 1 - 2 * (xx + yy);
  return p;
}

class RigidMeshSource final : public FrameSource {
 public:
  RigidMeshSource(std::string name, std::string origin, StaticMesh mesh, RigidMotion motion, uint32_t frames)
      : origin_(std::move(origin)), mesh_(std::move(mesh)), motion_(std::move(motion)), frames_(frames) {
    topology_.faces = mesh_.faces;
    topology_.num_vertices = uint32_t(mesh_.positions.size());
    topology_.objects.push_back({std::move(name), 0, uint32_t(mesh_.faces.size()), true});
    rigid_pose(motion_, 0);  // a zero axis fails here, not in the middle of a run
  }
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return frames_; }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    if (k >= frames_)
      fail(origin_ + ": frame " + std::to_string(k) + " out of range (" + std::to_string(frames_) + " frames)");
    const Pose pose = rigid_pose(motion_, k);
    out.resize(mesh_.positions.size());
    for (size_t v = 0; v < out.size(); ++v) {
      const dvec3 p = pose.apply(mesh_.positions[v]);
      out[v] = {p.x, p.y, p.z};
    }
    check_frame(out, topology_, origin_, k);
  }
  std::string describe() const override {
    return "rigid mesh " + origin_ + ": " + std::to_string(mesh_.faces.size()) + " triangles, " +
           (motion_.keys.empty() ? "parametric motion" : std::to_string(motion_.keys.size()) + " motion keys") +
           ", " + std::to_string(frames_) + " frames";
  }

 private:
  std::string origin_;
  StaticMesh mesh_;
  RigidMotion motion_;
  uint32_t frames_;
  Topology topology_;
};

}  // namespace

StaticMesh load_static_mesh(const std::filesystem::path& file, double scale, bool center) {
  Topology topology;
  std::vector<vec3d> positions;
  if (lower_extension(file) == ".obj") {
    // The plain reader: assimp's OBJ numbers can be ulps off.
    read_mesh_file(file, topology, positions);
  } else {
    // A file of several objects (BLEND, 3DS, glTF) places its meshes by node transforms; the
    // keyframe loader applies them (one keyframe: the file as it is).
    const auto still = open_keyframe_mesh({file, 0, 1});
    topology = still->topology();
    still->positions(0, positions);
  }
  check_frame(positions, topology, file.string(), 0);
  std::map<std::tuple<uint64_t, uint64_t, uint64_t>, uint32_t> first;
  std::vector<uint32_t> weld(positions.size());
  std::vector<vec3d> welded;
  for (size_t v = 0; v < positions.size(); ++v) {
    const vec3d& p = positions[v];
    const auto [it, added] = first.emplace(
        std::make_tuple(std::bit_cast<uint64_t>(p.x), std::bit_cast<uint64_t>(p.y), std::bit_cast<uint64_t>(p.z)),
        uint32_t(welded.size()));
    if (added) welded.push_back(positions[v]);
    weld[v] = it->second;
  }
  const vec3d centre = center ? bounds_centre(welded) : vec3d{0, 0, 0};
  const dvec3 c{centre.x, centre.y, centre.z};
  StaticMesh mesh;
  for (const vec3d& p : welded) mesh.positions.push_back(scale * (dvec3{p.x, p.y, p.z} - c));
  for (const Tri& t : topology.faces) mesh.faces.push_back({weld[t.v0], weld[t.v1], weld[t.v2]});
  return mesh;
}

Pose rigid_pose(const RigidMotion& m, uint32_t frame) {
  Quat q;
  dvec3 t;
  if (m.keys.empty()) {
    const double s = frame / m.fps;
    q = axis_angle(m.axis, m.angle + m.angular_velocity * s, "motion");
    t = m.position + s * m.velocity;
  } else {
    const auto& keys = m.keys;
    const auto key_quat = [&](size_t i) { return axis_angle(keys[i].axis, keys[i].angle, "motion key " + std::to_string(i)); };
    const double f = frame;
    if (f <= keys.front().frame) {
      q = key_quat(0), t = keys.front().position;
    } else if (f >= keys.back().frame) {
      q = key_quat(keys.size() - 1), t = keys.back().position;
    } else {
      const size_t i = size_t(std::upper_bound(keys.begin(), keys.end(), f,
                                               [](double x, const RigidKey& k) { return x < k.frame; }) -
                              keys.begin()) - 1;
      const double w = (f - keys[i].frame) / (keys[i + 1].frame - keys[i].frame);
      q = slerp(key_quat(i), key_quat(i + 1), w);
      t = keys[i].position + w * (keys[i + 1].position - keys[i].position);
    }
  }
  Pose pose = from_quat(q);
  // x = R (p - pivot) + pivot + t.
  pose.t = t + m.pivot - pose.rotate(m.pivot);
  return pose;
}

std::unique_ptr<FrameSource> make_rigid_mesh(std::string name, std::string origin, StaticMesh mesh,
                                             RigidMotion motion, uint32_t frames) {
  return std::make_unique<RigidMeshSource>(std::move(name), std::move(origin), std::move(mesh), std::move(motion),
                                           frames);
}

}  // namespace cdb
