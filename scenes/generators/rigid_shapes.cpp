#include "scenes/generators/rigid_shapes.h"

#include <algorithm>
#include <utility>

#include "scenes/generators/subdivision.h"

namespace cdb::scene {

RigidMesh icosphere(uint32_t level, double radius) {
  const double g = (1.0 + std::sqrt(5.0)) / 2.0;
  RigidMesh m;
  m.vertices = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
                {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  const std::vector<Tri> icosahedron = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                                        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},   {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                                        {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : m.vertices) v = normalized(v);
  // Each midpoint pushed onto the sphere as it is made (half the sum normalizes to the same
  // bits as the sum: scaling by a power of two is exact).
  const Subdivision s = subdivide(icosahedron, uint32_t(m.vertices.size()), level);
  s.apply(m.vertices, [](dvec3 p) { return normalized(p); });
  m.faces = s.faces;
  for (auto& v : m.vertices) v = radius * v;
  return m;
}

RigidMesh revolve(const Profile& profile, uint32_t segments) {
  RigidMesh m;
  std::vector<uint32_t> ring_start;
  for (const ProfilePoint& p : profile) {
    ring_start.push_back(uint32_t(m.vertices.size()));
    if (p.rho == 0) {
      m.vertices.push_back({0, p.y, 0});
      continue;
    }
    for (uint32_t s = 0; s < segments; ++s) {
      const double a = 6.283185307179586 * s / segments;
      m.vertices.push_back({p.rho * std::cos(a), p.y, p.rho * std::sin(a)});
    }
  }
  auto at = [&](size_t ring, uint32_t s) {
    return profile[ring].rho == 0 ? ring_start[ring] : ring_start[ring] + s % segments;
  };
  for (size_t r = 0; r + 1 < profile.size(); ++r) {
    const bool a_axis = profile[r].rho == 0, b_axis = profile[r + 1].rho == 0;
    if (a_axis && b_axis) continue;
    for (uint32_t s = 0; s < segments; ++s) {
      const uint32_t a0 = at(r, s), a1 = at(r, s + 1), b0 = at(r + 1, s), b1 = at(r + 1, s + 1);
      if (!a_axis) m.faces.push_back({a0, a1, b1});
      if (!b_axis) m.faces.push_back({a0, b1, b0});
    }
  }
  return m;
}

uint32_t revolve_triangles(const Profile& profile, uint32_t segments) {
  uint32_t n = 0;
  for (size_t r = 0; r + 1 < profile.size(); ++r)
    n += segments * (uint32_t(profile[r].rho != 0) + uint32_t(profile[r + 1].rho != 0));
  return n;
}

Profile cone_profile(double radius, double height) { return {{0, 0}, {radius, 0}, {0, height}}; }

Profile capsule_profile(double radius, double height, uint32_t arc) {
  Profile p;
  for (uint32_t i = 0; i <= arc; ++i) {  // bottom hemisphere, from the pole up to the equator
    const double a = -1.5707963267948966 + 1.5707963267948966 * i / arc;
    p.push_back({radius * std::cos(a), radius * std::sin(a)});
  }
  for (uint32_t i = 0; i <= arc; ++i) {  // top hemisphere
    const double a = 1.5707963267948966 * i / arc;
    p.push_back({radius * std::cos(a), height + radius * std::sin(a)});
  }
  p.front().rho = 0;  // exactly on the axis, so the poles are single vertices
  p.back().rho = 0;
  return p;
}

void append_faces(const RigidMesh& mesh, uint32_t base, std::vector<Tri>& faces) {
  for (const Tri& t : mesh.faces) faces.push_back({base + t.v0, base + t.v1, base + t.v2});
}

}  // namespace cdb::scene
