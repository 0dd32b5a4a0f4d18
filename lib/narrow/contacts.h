#pragma once
// Narrow-phase accuracy of a broad phase: how many of its reported pairs are pairs of
// triangles in contact, that is within a contact distance of each other (0: intersecting;
// triangle_intersect.h and proximity.h, both exact). Host only; `run --check` calls it after
// the timed frame.
#include <cstdint>
#include <vector>

#include "cdbench/core/pair.h"
#include "cdbench/core/vec.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

// What `run --check` counts as a contact: triangles within `distance` (--contact-distance),
// over the frame interval sampled at `substeps` steps (--contact-substeps).
struct ContactCheck {
  float distance = 0.0f;
  uint32_t substeps = 8;
};

// Pairs of `pairs` whose closed triangles lie within `distance` of each other (0: share a
// point) at the positions `vertices`. Triangles sharing a vertex always count: they touch.
uint64_t count_true_contacts(const std::vector<Tri>& faces, const std::vector<vec3f>& vertices,
                             const std::vector<PrimPair>& pairs, float distance = 0.0f);

// Pairs of `pairs` whose triangles come within `distance` at one of the substeps + 1 sampled
// times of the frame interval: each vertex moves linearly from `previous` to `current`, its
// position at t = s / substeps (s = 0 .. substeps, both frames included) interpolated in
// float as (1 - t) previous + t current, as a simulator stepping the interval would. Sampling
// misses contacts that begin and end between two samples, so this is a lower bound on the
// pairs in contact at some time of the interval (no exact continuous test is built).
uint64_t count_interval_contacts(const std::vector<Tri>& faces, const std::vector<vec3f>& previous,
                                 const std::vector<vec3f>& current, const std::vector<PrimPair>& pairs,
                                 float distance, uint32_t substeps);

// The pairs of `pairs` whose closed triangles lie within `distance` (0: share a point) and
// that share no vertex: the contacts a picture marks (triangles sharing a vertex touch by
// construction; marked, they would mark every triangle of a mesh).
std::vector<PrimPair> contacts_apart_from_neighbours(const std::vector<Tri>& faces, const std::vector<vec3f>& vertices,
                                                     const std::vector<PrimPair>& pairs, float distance);

// True contacts / reported pairs; 1 when there are no pairs (nothing reported wrongly).
inline double contact_precision(uint64_t contacts, uint64_t pairs) {
  return pairs ? double(contacts) / double(pairs) : 1.0;
}

}  // namespace cdb
