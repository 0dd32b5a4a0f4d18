#include "narrow/contacts.h"

#include <cstddef>

#include "narrow/triangle_intersect.h"

namespace cdb {

uint64_t count_true_contacts(const std::vector<Tri>& faces, const std::vector<vec3f>& vertices,
                             const std::vector<PrimPair>& pairs) {
  uint64_t contacts = 0;
  const std::ptrdiff_t n = std::ptrdiff_t(pairs.size());
#pragma omp parallel for schedule(static) reduction(+ : contacts)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    const Tri s = faces[pairs[size_t(k)].a], t = faces[pairs[size_t(k)].b];
    contacts += triangles_intersect(vertices[s.v0], vertices[s.v1], vertices[s.v2], vertices[t.v0],
                                    vertices[t.v1], vertices[t.v2]);
  }
  return contacts;
}

}  // namespace cdb
