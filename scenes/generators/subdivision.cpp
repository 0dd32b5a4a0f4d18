#include "scenes/generators/subdivision.h"

#include <algorithm>
#include <map>

namespace cdb::scene {

Subdivision subdivide(const std::vector<Tri>& faces, uint32_t vertices, uint32_t levels) {
  Subdivision s;
  s.base_vertices = vertices;
  s.faces = faces;
  for (uint32_t l = 0; l < levels; ++l) {
    // One midpoint per edge, shared by the edge's two triangles.
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      const auto [it, added] = midpoint.try_emplace(key, s.vertices());
      if (added) s.midpoints.push_back(key);
      return it->second;
    };
    std::vector<Tri> finer;
    finer.reserve(4 * s.faces.size());
    for (const Tri& t : s.faces) {
      const uint32_t ab = mid(t.v0, t.v1), bc = mid(t.v1, t.v2), ca = mid(t.v2, t.v0);
      finer.push_back({t.v0, ab, ca});
      finer.push_back({t.v1, bc, ab});
      finer.push_back({t.v2, ca, bc});
      finer.push_back({ab, bc, ca});
    }
    s.faces = std::move(finer);
  }
  return s;
}

void Subdivision::apply(std::vector<dvec3>& positions, const std::function<dvec3(dvec3)>& project) const {
  positions.resize(base_vertices);
  positions.reserve(vertices());
  for (const auto& [a, b] : midpoints) {
    const dvec3 m = 0.5 * (positions[a] + positions[b]);
    positions.push_back(project ? project(m) : m);
  }
}

}  // namespace cdb::scene
