#pragma once
// The connected pieces of the faces one hierarchy holds: faces that share a vertex are in
// one piece. A piece ordered build (--build-pieces, bvh/build.h PieceOrder) keeps each
// piece's faces in subtrees of their own, so a tree refitted while its pieces move apart
// (a statue shattering, bodies falling) loosens only the levels above the pieces.
#include <cstdint>
#include <vector>

#include "cdbench/geometry/mesh.h"

namespace cdb {

// Pieces a piece ordered build takes at most: the piece index takes up to 12 key bits.
inline constexpr uint32_t kMaxPieceBits = 12;
// --build-pieces auto orders by pieces of at least this many faces on average: objects, not
// a soup of separate triangles or boxes, whose keys would order a cell's faces by piece
// index instead of by place.
inline constexpr uint32_t kPieceMinMeanFaces = 16;

struct MeshPieces {
  // Per subset position: its piece, numbered in the order of the pieces' first faces.
  std::vector<uint32_t> leaf_piece;
  // Per piece: the subset position of its first face, whose centroid places the piece.
  std::vector<uint32_t> piece_first;
  uint32_t count() const { return uint32_t(piece_first.size()); }
};

// The pieces of the faces of `subset` (list on the host, or every face), by union-find over
// the vertices; a face with an out-of-range vertex index is a piece of its own.
MeshPieces mesh_pieces(const std::vector<Tri>& faces, uint32_t num_vertices, const std::vector<uint32_t>& subset);

// Key bits a piece index needs: 0 for one piece (or none), else ceil(log2(count)).
uint32_t piece_bits(uint32_t count);

}  // namespace cdb
