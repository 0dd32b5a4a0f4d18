#pragma once
// Narrow-phase accuracy of a broad phase: how many of its reported pairs are pairs of
// triangles that truly intersect (triangle_intersect.h, exact). Host only; `run --check`
// calls it after the timed frame.
#include <cstdint>
#include <vector>

#include "core/pair.h"
#include "core/vec.h"
#include "geometry/mesh.h"

namespace cdb {

// Pairs of `pairs` whose closed triangles share a point (faces and vertex positions of one
// frame). Triangles sharing a vertex always count: they touch there.
uint64_t count_true_contacts(const std::vector<Tri>& faces, const std::vector<vec3f>& vertices,
                             const std::vector<PrimPair>& pairs);

// True contacts / reported pairs; 1 when there are no pairs (nothing reported wrongly).
inline double contact_precision(uint64_t contacts, uint64_t pairs) {
  return pairs ? double(contacts) / double(pairs) : 1.0;
}

}  // namespace cdb
