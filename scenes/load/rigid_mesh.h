#pragma once
// A rigid object: one static mesh file (any format assimp reads, node transforms applied;
// OBJ through the plain reader) placed once, then moved by a rigid transform per frame,
// evaluated in double:
//   x_k = R_k (p - pivot) + pivot + t_k,   p = scale * (file position - centre)
// with either a parametric motion (t_k = position + velocity * s, R_k = rotation about
// `axis` by angle + angular_velocity * s, s = k / fps seconds) or keyframes (position and
// axis-angle rotation at given frames; positions interpolated linearly, rotations by
// slerp along the shorter arc; before the first key and after the last the end pose holds).
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "scenes/generators/dvec.h"
#include "cdbench/geometry/frame_source.h"

namespace cdb {

// The mesh as placed in the scene before any motion, welded: vertices of one file at the
// same position (bit for bit) take one index, as formats such as OFF and STL give each face
// its own corners and co-vertex filtering needs the shared ones.
struct StaticMesh {
  std::vector<Tri> faces;
  std::vector<scene::dvec3> positions;
};

// `center`: move the file's bounding-box centre to the origin before scaling (scans come
// in their scanner's coordinates).
StaticMesh load_static_mesh(const std::filesystem::path& file, double scale, bool center);

struct RigidKey {
  double frame = 0;
  scene::dvec3 position, axis{0, 1, 0};
  double angle = 0;  // radians
};

struct RigidMotion {
  scene::dvec3 pivot;  // rotations turn about this point of the placed mesh
  // Parametric, used when `keys` is empty.
  double fps = 30;
  scene::dvec3 position, velocity, axis{0, 1, 0};
  double angle = 0, angular_velocity = 0;  // radians, radians per second
  std::vector<RigidKey> keys;              // frames strictly increasing
};

// x -> R x + t for frame k (the pivot folded into t). Throws naming the key when an axis is
// zero.
scene::Pose rigid_pose(const RigidMotion& motion, uint32_t frame);

// One rigid object named `name` over `frames` frames.
std::unique_ptr<FrameSource> make_rigid_mesh(std::string name, std::string origin, StaticMesh mesh,
                                             RigidMotion motion, uint32_t frames);

}  // namespace cdb
