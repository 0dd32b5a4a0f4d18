#include "cdbench/geometry/mesh_pieces.h"

#include <numeric>

namespace cdb {

namespace {

// Union-find over vertices, path halving and union by index (the smaller root wins).
struct VertexSets {
  std::vector<uint32_t> parent;
  explicit VertexSets(uint32_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
  void join(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a < b) parent[b] = a;
    else if (b < a) parent[a] = b;
  }
};

}  // namespace

MeshPieces mesh_pieces(const std::vector<Tri>& faces, uint32_t num_vertices, const std::vector<uint32_t>& subset) {
  const size_t n = subset.empty() ? faces.size() : subset.size();
  const auto face_at = [&](size_t k) { return subset.empty() ? uint32_t(k) : subset[k]; };
  const auto valid = [&](const Tri& t) { return t.v0 < num_vertices && t.v1 < num_vertices && t.v2 < num_vertices; };
  VertexSets sets(num_vertices);
  for (size_t k = 0; k < n; ++k) {
    const Tri& t = faces[face_at(k)];
    if (!valid(t)) continue;
    sets.join(t.v0, t.v1);
    sets.join(t.v0, t.v2);
  }
  MeshPieces p;
  p.leaf_piece.resize(n);
  constexpr uint32_t kNone = ~0u;
  std::vector<uint32_t> piece_of_root(num_vertices, kNone);
  for (size_t k = 0; k < n; ++k) {
    const Tri& t = faces[face_at(k)];
    uint32_t* slot = nullptr;
    if (valid(t)) slot = &piece_of_root[sets.find(t.v0)];
    if (!slot || *slot == kNone) {
      const uint32_t piece = p.count();
      p.piece_first.push_back(uint32_t(k));
      if (slot) *slot = piece;
      p.leaf_piece[k] = piece;
    } else {
      p.leaf_piece[k] = *slot;
    }
  }
  return p;
}

uint32_t piece_bits(uint32_t count) {
  uint32_t bits = 0;
  while (count > 1 && (uint64_t(1) << bits) < count) ++bits;
  return bits;
}

}  // namespace cdb
