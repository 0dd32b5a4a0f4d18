#pragma once
// Midpoint subdivision of a triangle mesh: each level splits every triangle into four at its
// edges' midpoints. The new vertices are flat (no smoothing), so the surface is the same and
// only its triangles are smaller: a scene gets a finer mesh of the same shape, as a
// simulation's collision mesh is often finer than the model it was skinned from.
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "cdbench/geometry/mesh.h"
#include "scenes/generators/dvec.h"

namespace cdb::scene {

struct Subdivision {
  uint32_t base_vertices = 0;  // the coarse mesh's vertices, which keep their indices
  std::vector<Tri> faces;      // 4^levels faces for each coarse face
  // New vertex base_vertices + i is the midpoint of vertices midpoints[i] (each an earlier
  // vertex, coarse or new), so positions are made in this order.
  std::vector<std::pair<uint32_t, uint32_t>> midpoints;

  uint32_t vertices() const { return base_vertices + uint32_t(midpoints.size()); }
  // The coarse mesh's positions followed by the new vertices'; with `project`, each new
  // vertex is projected as it is made (onto the unit sphere: icosphere), so later midpoints
  // are of projected vertices.
  void apply(std::vector<dvec3>& positions, const std::function<dvec3(dvec3)>& project = {}) const;
};

// `levels` 0 gives the mesh as it is.
Subdivision subdivide(const std::vector<Tri>& faces, uint32_t vertices, uint32_t levels);

}  // namespace cdb::scene
