#pragma once
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "cdbench/geometry/box_grid.h"
#include "cdbench/geometry/objects.h"

#include "cdbench/core/aabb.h"
#include "cdbench/core/hd.h"
#include "cdbench/core/outward_rounding.h"
#include "cdbench/core/vec.h"

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
  // Faces that stand for input boxes rather than triangles (io/box_stream.h): degenerate
  // (min, max, max) faces whose box is the input box, but whose "triangle" is only the box's
  // diagonal, so contact tests on real triangles must not run on them.
  uint32_t box_faces = 0;
};

// What kernels see of a mesh frame: plain pointers, passed by value.
// The speed/accuracy knobs every box goes through (docs/design.md "Speed/accuracy knobs"):
// `prev_vertices` (null: none) makes each box also bound the triangle at the previous
// frame (swept boxes), `grid` (null: none) snaps it outward onto this frame's 16-bit grid
// (--box-precision q16; executor memory, written on the executor each frame), `widen`
// moves each side out by one float spacing (--box-precision fp64 with a margin: the
// positions' rounding error, geometry/position_rounding.h), and `margin` (absolute, scene
// units, >= 0) inflates it on every side (fat boxes).
struct MeshView {
  const vec3f* vertices;
  const Tri* faces;
  uint32_t num_faces;
  const vec3f* prev_vertices = nullptr;
  float margin = 0.0f;
  const BoxGrid* grid = nullptr;
  bool widen = false;
};

// The one per-face box every pipeline and baseline uses. Each step only widens the box and
// every rounding goes outward, so the box contains the real-valued box the knobs describe:
// the exact (swept) triangle box, snapped to the grid, grown by the margin.
CDB_HD_INLINE void face_box(const MeshView& m, uint32_t f, vec4f& lo, vec4f& hi) {
  const Tri t = m.faces[f];
  triangle_box(m.vertices[t.v0], m.vertices[t.v1], m.vertices[t.v2], lo, hi);
  if (m.prev_vertices) {
    vec4f plo, phi;
    triangle_box(m.prev_vertices[t.v0], m.prev_vertices[t.v1], m.prev_vertices[t.v2], plo, phi);
    lo = min_xyz(lo, plo, 0.0f);
    hi = max_xyz(hi, phi, 0.0f);
  }
  if (m.grid) snap_box_outward(*m.grid, lo, hi);
  if (m.widen) {
    constexpr float kDown = -std::numeric_limits<float>::infinity(), kUp = std::numeric_limits<float>::infinity();
    lo = {nextafterf(lo.x, kDown), nextafterf(lo.y, kDown), nextafterf(lo.z, kDown), 0.0f};
    hi = {nextafterf(hi.x, kUp), nextafterf(hi.y, kUp), nextafterf(hi.z, kUp), 0.0f};
  }
  if (m.margin != 0.0f) {
    const float e = m.margin;
    lo = {sub_round_down(lo.x, e), sub_round_down(lo.y, e), sub_round_down(lo.z, e), 0.0f};
    hi = {add_round_up(hi.x, e), add_round_up(hi.y, e), add_round_up(hi.z, e), 0.0f};
  }
}

// face_box of every face, one index each.
struct FaceBoxFn {
  MeshView mesh;
  vec4f* lo;
  vec4f* hi;
  CDB_HD void operator()(uint32_t f) const { face_box(mesh, f, lo[f], hi[f]); }
};

}  // namespace cdb
