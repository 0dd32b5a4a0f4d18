#pragma once
#include <cstdint>
#include <vector>

#include "geometry/objects.h"

#include "core/aabb.h"
#include "core/hd.h"
#include "core/vec.h"

namespace cdb {

// Vertex indices of one triangle, 0-based.
struct Tri {
  uint32_t v0, v1, v2;
};
static_assert(sizeof(Tri) == 3 * sizeof(uint32_t), "faces are read as 3 vertex indices each");

// Fixed topology of a scene's triangles; per-frame positions come separately.
struct Topology {
  std::vector<Tri> faces;
  uint32_t num_vertices = 0;
  std::vector<SceneObject> objects;  // empty: one unnamed object
  ObjectQueries queries;             // not declared: every pair
};

// What kernels see of a mesh frame: plain pointers, passed by value.
struct MeshView {
  const vec3f* vertices;
  const Tri* faces;
  uint32_t num_faces;
};

CDB_HD_INLINE void face_box(const MeshView& m, uint32_t f, vec4f& lo, vec4f& hi) {
  const Tri t = m.faces[f];
  triangle_box(m.vertices[t.v0], m.vertices[t.v1], m.vertices[t.v2], lo, hi);
}

}  // namespace cdb
