#pragma once
#include "cdbench/core/hd.h"

namespace cdb {

// Packed 3-vector: vertex positions as they come from meshes.
template <class T>
struct vec3 {
  T x, y, z;
};

// Padded 4-vector: box corners, so a corner is one 16-byte (float) load on the GPU.
template <class T>
struct alignas(4 * sizeof(T)) vec4 {
  T x, y, z, w;
};

using vec3f = vec3<float>;
using vec4f = vec4<float>;
// Positions as scenes hold them (--box-precision fp64 keeps them; docs/design.md "Box precision").
using vec3d = vec3<double>;
using vec4d = vec4<double>;

template <class T>
CDB_HD_INLINE T min_of(T a, T b) { return b < a ? b : a; }
template <class T>
CDB_HD_INLINE T max_of(T a, T b) { return a < b ? b : a; }

// The corners of the union of two boxes (lanes x, y, z), lane w given: a box's w lanes carry
// other data (links, node_ref.h), so each merge names what its result keeps there.
CDB_HD_INLINE vec4f min_xyz(const vec4f& a, const vec4f& b, float w) {
  return {min_of(a.x, b.x), min_of(a.y, b.y), min_of(a.z, b.z), w};
}
CDB_HD_INLINE vec4f max_xyz(const vec4f& a, const vec4f& b, float w) {
  return {max_of(a.x, b.x), max_of(a.y, b.y), max_of(a.z, b.z), w};
}

}  // namespace cdb
