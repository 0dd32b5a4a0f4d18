#include "cdbench/narrow/contacts.h"

#include <cstddef>

#include "cdbench/core/error.h"
#include "cdbench/narrow/proximity.h"
#include "cdbench/narrow/triangle_intersect.h"

namespace cdb {
namespace {

vec3f interpolate(const vec3f& from, const vec3f& to, float t) {
  const float s = 1.0f - t;
  return {s * from.x + t * to.x, s * from.y + t * to.y, s * from.z + t * to.z};
}

}  // namespace

uint64_t count_true_contacts(const std::vector<Tri>& faces, const std::vector<vec3f>& vertices,
                             const std::vector<PrimPair>& pairs, float distance) {
  uint64_t contacts = 0;
  const std::ptrdiff_t n = std::ptrdiff_t(pairs.size());
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : contacts)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const Tri s = faces[pairs[size_t(k)].a], t = faces[pairs[size_t(k)].b];
    contacts += triangles_within(vertices[s.v0], vertices[s.v1], vertices[s.v2], vertices[t.v0], vertices[t.v1],
                                 vertices[t.v2], distance);
  }
  return contacts;
}

std::vector<PrimPair> contacts_apart_from_neighbours(const std::vector<Tri>& faces, const std::vector<vec3f>& vertices,
                                                     const std::vector<PrimPair>& pairs, float distance) {
  std::vector<uint8_t> touch(pairs.size(), 0);
  const std::ptrdiff_t n = std::ptrdiff_t(pairs.size());
#pragma omp parallel for schedule(dynamic, 1024)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const Tri s = faces[pairs[size_t(k)].a], t = faces[pairs[size_t(k)].b];
    bool shared = false;
    for (uint32_t u : {s.v0, s.v1, s.v2})
      for (uint32_t v : {t.v0, t.v1, t.v2}) shared |= u == v;
    touch[size_t(k)] = !shared && triangles_within(vertices[s.v0], vertices[s.v1], vertices[s.v2], vertices[t.v0],
                                                   vertices[t.v1], vertices[t.v2], distance);
  }
  std::vector<PrimPair> contacts;
  for (size_t k = 0; k < pairs.size(); ++k)
    if (touch[k]) contacts.push_back(pairs[k]);
  return contacts;
}

uint64_t count_interval_contacts(const std::vector<Tri>& faces, const std::vector<vec3f>& previous,
                                 const std::vector<vec3f>& current, const std::vector<PrimPair>& pairs,
                                 float distance, uint32_t substeps) {
  if (substeps == 0) fail("contact substeps must be at least 1");
  if (previous.size() != current.size()) fail("previous and current frames differ in vertex count");
  uint64_t contacts = 0;
  const std::ptrdiff_t n = std::ptrdiff_t(pairs.size());
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : contacts)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const Tri s = faces[pairs[size_t(k)].a], t = faces[pairs[size_t(k)].b];
    const uint32_t corners[6] = {s.v0, s.v1, s.v2, t.v0, t.v1, t.v2};
    for (uint32_t step = 0; step <= substeps; ++step) {
      const float time = float(step) / float(substeps);
      vec3f p[6];
      for (int c = 0; c < 6; ++c) p[c] = interpolate(previous[corners[c]], current[corners[c]], time);
      if (triangles_within(p[0], p[1], p[2], p[3], p[4], p[5], distance)) {
        ++contacts;
        break;
      }
    }
  }
  return contacts;
}

}  // namespace cdb
