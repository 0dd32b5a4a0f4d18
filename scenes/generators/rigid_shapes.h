#pragma once
// Triangle meshes of the rigid bodies that scenes put next to their cloth (balls, cones,
// funnels, poles), in body coordinates. A scene places them with a Pose each frame.
#include <cstdint>
#include <vector>

#include "scenes/generators/dvec.h"
#include "cdbench/geometry/mesh.h"

namespace cdb::scene {

struct RigidMesh {
  std::vector<dvec3> vertices;
  std::vector<Tri> faces;
};

// A meridian point of a surface of revolution about the y axis: radius and height.
struct ProfilePoint {
  double rho, y;
};
using Profile = std::vector<ProfilePoint>;

// Geodesic sphere: an icosahedron subdivided `level` times, 20 * 4^level triangles.
RigidMesh icosphere(uint32_t level, double radius);

// The profile swept about the y axis in `segments` steps. Points on the axis (rho == 0)
// become one vertex (a fan); every other profile edge becomes 2 * segments triangles.
RigidMesh revolve(const Profile& profile, uint32_t segments);
uint32_t revolve_triangles(const Profile& profile, uint32_t segments);

// Solid cone, base centred on the origin, apex at (0, height, 0): 2 * segments triangles.
Profile cone_profile(double radius, double height);
// Capsule along y from 0 to `height` (hemisphere centres), `arc` steps per hemisphere.
Profile capsule_profile(double radius, double height, uint32_t arc);

// Appends the mesh's faces to `faces`, vertex indices offset by `base`.
void append_faces(const RigidMesh& mesh, uint32_t base, std::vector<Tri>& faces);

}  // namespace cdb::scene
