#include "cdbench/oracle/sweep_oracle.h"

#include <algorithm>
#include <numeric>

#include "cdbench/core/aabb.h"

namespace cdb {
namespace {

template <class T>
std::vector<PrimPair> sweep_pairs_of(const Topology& topology, const std::vector<vec3<T>>& vertices,
                                     bool skip_adjacent) {
  const size_t n = topology.faces.size();
  PairFilterTables filter;
  if (topology.queries.declared) filter = pair_filter_tables(topology.objects, topology.queries, n);
  std::vector<vec4<T>> lo(n), hi(n);
  for (size_t f = 0; f < n; ++f) {
    const Tri t = topology.faces[f];
    triangle_box(vertices[t.v0], vertices[t.v1], vertices[t.v2], lo[f], hi[f]);
  }
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::stable_sort(order.begin(), order.end(),
                   [&](uint32_t a, uint32_t b) { return lo[a].x < lo[b].x; });
  std::vector<PrimPair> pairs;
  for (size_t s = 0; s < n; ++s) {
    const uint32_t i = order[s];
    for (size_t u = s + 1; u < n; ++u) {
      const uint32_t j = order[u];
      if (lo[j].x > hi[i].x) break;
      if (!overlaps(lo[i], hi[i], lo[j], hi[j])) continue;
      const Tri a = topology.faces[i], b = topology.faces[j];
      const bool adjacent = a.v0 == b.v0 || a.v0 == b.v1 || a.v0 == b.v2 || a.v1 == b.v0 ||
                            a.v1 == b.v1 || a.v1 == b.v2 || a.v2 == b.v0 || a.v2 == b.v1 ||
                            a.v2 == b.v2;
      if (skip_adjacent && adjacent) continue;
      if (topology.queries.declared &&
          !((filter.partners[filter.face_object[i]] >> filter.face_object[j]) & 1u))
        continue;
      pairs.push_back(make_pair_ordered(i, j));
    }
  }
  std::sort(pairs.begin(), pairs.end(),
            [](PrimPair a, PrimPair b) { return pair_key(a) < pair_key(b); });
  return pairs;
}

}  // namespace

std::vector<PrimPair> sweep_oracle_pairs(const Topology& topology, const std::vector<vec3f>& vertices,
                                         bool skip_adjacent) {
  return sweep_pairs_of(topology, vertices, skip_adjacent);
}

std::vector<PrimPair> sweep_oracle_pairs(const Topology& topology, const std::vector<vec3d>& vertices,
                                         bool skip_adjacent) {
  return sweep_pairs_of(topology, vertices, skip_adjacent);
}

}  // namespace cdb
