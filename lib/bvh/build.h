#pragma once
// Apetrei's agglomerative LBVH build (Apetrei 2014, "Fast and simple agglomerative LBVH
// construction"; paper §2, Fig. 2.1). One thread per leaf climbs the tree; at each step the
// current range [l, r] merges towards the neighbour it is more similar to, and internal node
// k is the split between leaves k and k+1 (k = rightmost leaf of its left child). The first
// thread to reach a node stops; the second completes it. The handoff goes through
// atomic_exchange_acq_rel and load_coherent (core/atomics.h): fence, atomic, fence, L1
// bypass.
#include <cstdint>

#include "cdbench/exec/balance.h"
#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/atomics.h"
#include "cdbench/core/morton.h"
#include "cdbench/geometry/face_subset.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

// Boxes of a subset's faces, in subset order.
struct SubsetFaceBoxFn {
  MeshView mesh;
  FaceSubset subset;
  vec4f* lo;
  vec4f* hi;
  CDB_HD void operator()(uint32_t k) const { face_box(mesh, subset.face(k), lo[k], hi[k]); }
};

// The sorted leaves' boxes: leaf k takes the box of the face its key sort put there. The
// link lanes are written by the depth-first layout (bvh/order.h).
struct GatherLeafBoxesFn {
  const uint32_t* order;
  const vec4f* lo;
  const vec4f* hi;
  NodeBox* leaf_box;
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t p = order[k];
    leaf_box[k] = {lo[p], hi[p]};
  }
};

// Sorted leaves name subset positions after the key sort; this makes them mesh faces.
struct SubsetLeafPrimFn {
  FaceSubset subset;
  uint32_t* leaf_prim;
  CDB_HD void operator()(uint32_t i) const { leaf_prim[i] = subset.face(leaf_prim[i]); }
};

// Box of a primitive's centroid, for the Morton normalization. Halving before adding keeps
// huge coordinates (1e38) finite.
struct CentroidFn {
  const vec4f* lo;
  const vec4f* hi;
  CDB_HD Aabb<float> operator()(uint32_t i) const {
    const vec4f a = lo[i], b = hi[i];
    const vec4f c{a.x * 0.5f + b.x * 0.5f, a.y * 0.5f + b.y * 0.5f, a.z * 0.5f + b.z * 0.5f, 0};
    return {c, c};
  }
};

// Bits a group index takes at the top of a grouped Morton key: up to 64 groups (objects,
// kMaxQueryObjects).
inline constexpr int kGroupBits = 6;
static_assert((size_t(1) << kGroupBits) >= kMaxQueryObjects, "a group index per object");

// A piece ordered key (--build-pieces, geometry/mesh_pieces.h): per subset position its
// piece, per piece the subset position of its first face. The key puts the Morton code of
// the piece's first face, cut to piece_cell_bits, above the piece index (piece_bits) above
// the leaf's own code, so each piece's leaves are contiguous and form subtrees of their own,
// and the levels above them are a Morton tree over the pieces as they lie at the build.
struct PieceOrder {
  const uint32_t* leaf_piece = nullptr;
  const uint32_t* piece_first = nullptr;
  uint32_t piece_bits = 0;
  CDB_HD_INLINE bool on() const { return leaf_piece != nullptr; }
};

// Bits of a piece's place (its first face's cell) at the top of a piece ordered key: 7 a
// dimension of the 63-bit code, 3 of the 30-bit one.
CDB_HD_INLINE int piece_cell_bits(MortonBits bits) { return 3 * (int(bits) / 9); }

// Whether a key of `bits` keeps a leaf's own code of at least a cell a dimension beside the
// piece's cell and index.
inline bool piece_order_fits(MortonBits bits, uint32_t piece_bits) {
  return int(bits) - piece_cell_bits(bits) - int(piece_bits) >= 3;
}

struct MortonFn {
  const vec4f* lo;
  const vec4f* hi;
  const Aabb<float>* centroid_box;
  MortonBits bits;
  uint64_t* keys;
  uint32_t* iota;
  // Optional grouping: per mesh face its group (object); primitive i is face subset.face(i).
  // A grouped key puts the group above the Morton code (which gives up its finest kGroupBits
  // bits), so each group's leaves are contiguous and form their own subtrees.
  const uint32_t* face_group;
  FaceSubset subset;
  PieceOrder pieces;
  CDB_HD void operator()(uint32_t i) const {
    const Aabb<float> s = *centroid_box;
    const uint64_t code = morton_code(unit_centroid(lo[i], hi[i], s.lo, s.hi), bits);
    const int b = int(bits);
    if (pieces.on()) {
      const uint32_t piece = pieces.leaf_piece[i];
      const uint32_t f = pieces.piece_first[piece];
      const int cell = piece_cell_bits(bits), below = b - cell - int(pieces.piece_bits);
      const uint64_t place = morton_code(unit_centroid(lo[f], hi[f], s.lo, s.hi), bits) >> (b - cell);
      keys[i] = (place << (b - cell)) | (uint64_t(piece) << below) | (code >> (b - below));
    } else {
      keys[i] = face_group ? (uint64_t(face_group[subset.face(i)]) << (b - kGroupBits)) | (code >> kGroupBits) : code;
    }
    iota[i] = i;
  }
};

// Dissimilarity of sorted leaves i and i+1. Equal codes fall back to the index (Karras'
// augmentation) below every distinct-code value, so identical centroids still give a
// balanced tree. Any strict order gives a valid tree; ties between equal values resolve to
// the left neighbour.
CDB_HD_INLINE uint64_t split_delta(const uint64_t* keys, uint32_t i) {
  const uint64_t x = keys[i] ^ keys[i + 1];
  return x != 0 ? (x | (uint64_t(1) << 63)) : uint64_t(i ^ (i + 1));
}

// What Apetrei's climb reads and writes: the sorted leaves' keys and boxes, their parents,
// and the build-numbered tree (internal node k = split between sorted leaves k and k+1).
struct ApetreiTree {
  const uint64_t* keys;
  TreeArrays leaves;
  BuildArrays build;

  CDB_HD_INLINE void set_parent(uint32_t child, uint32_t parent) const {
    if (is_leaf(child))
      leaves.leaf_parent[ref_index(child)] = parent;
    else
      build.parent[child] = parent;
  }
};

// Leaf i's climb over the sorted leaves [s, t]: the whole tree (s = 0, t = N-1) or one
// subtree being restructured (bvh/restructure.h), whose root stops the climb. Only keys in
// [s, t] are read.
CDB_HD_INLINE void apetrei_climb(const ApetreiTree& a, uint32_t i, uint32_t s, uint32_t t) {
  uint32_t l = i, r = i;
  uint32_t current = leaf_ref(i);
  const BuildArrays& b = a.build;
  vec4f lo = a.leaves.leaf_box[i].lo, hi = a.leaves.leaf_box[i].hi;
  for (;;) {
    const bool parent_is_right_split =
        l == s || (r != t && split_delta(a.keys, r) < split_delta(a.keys, l - 1));
    uint32_t parent, sibling;
    if (parent_is_right_split) {
      parent = r;  // current is the left child of internal node r
      b.left[parent] = current;
      a.set_parent(current, parent);
      const uint32_t other = atomic_exchange_acq_rel(&b.other_bound[parent], l);
      if (other == kNoNode) return;
      r = other;
      sibling = load_coherent(&b.right[parent]);
    } else {
      parent = l - 1;  // current is the right child of internal node l-1
      b.right[parent] = current;
      a.set_parent(current, parent);
      const uint32_t other = atomic_exchange_acq_rel(&b.other_bound[parent], r);
      if (other == kNoNode) return;
      l = other;
      sibling = load_coherent(&b.left[parent]);
    }
    const vec4f slo = is_leaf(sibling) ? a.leaves.leaf_box[ref_index(sibling)].lo
                                       : load_coherent(&b.lo[sibling]);
    const vec4f shi = is_leaf(sibling) ? a.leaves.leaf_box[ref_index(sibling)].hi
                                       : load_coherent(&b.hi[sibling]);
    lo = min_xyz(lo, slo, 0);
    hi = max_xyz(hi, shi, 0);
    b.lo[parent] = lo;
    b.hi[parent] = hi;
    b.first[parent] = l;
    b.last[parent] = r;
    atomic_add_relaxed(&b.count_log[l], 1u);
    current = parent;
    if (l == s && r == t) {
      b.parent[parent] = kNoNode;
      return;
    }
  }
}

struct ApetreiBuildFn {
  ApetreiTree tree;
  uint32_t n;
  CDB_HD void operator()(uint32_t i) const { apetrei_climb(tree, i, 0, n - 1); }
};

// The build scratch of an Lbvh as Apetrei's climb sees it, with `keys` sorted by leaf.
template <class Exec>
ApetreiTree apetrei_tree(Lbvh<Exec>& bvh, const uint64_t* keys) {
  return {keys, bvh.tree(), bvh.build()};
}

// The first step of a build: the boxes of a subset's faces, in subset order, into the
// build scratch. The only step that reads the mesh: a build ahead (--rebuild-ahead) runs it
// on the frame's stream and the rest on a side stream, which the next frame's upload then
// cannot race.
template <class Exec>
void build_boxes(Exec& exec, Lbvh<Exec>& bvh, const MeshView& mesh, FaceSubset subset) {
  bvh.reserve(exec, subset.count);
  if (subset.count > 0)
    exec.for_each_n(subset.count, SubsetFaceBoxFn{mesh, subset, bvh.prim_lo.data(), bvh.prim_hi.data()});
}

// The rest of the build from those boxes: Morton codes, radix sort, Apetrei build.
template <class Exec>
void build_from_boxes(Exec& exec, Lbvh<Exec>& bvh, MortonBits bits, FaceSubset subset,
                      const uint32_t* face_group = nullptr, PieceOrder pieces = {}) {
  const uint32_t n = subset.count;
  bvh.morton_bits = bits;
  if (n == 0) return;
  exec.reduce_box(n, CentroidFn{bvh.prim_lo.data(), bvh.prim_hi.data()}, bvh.centroid_box.data(),
                  bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(n, MortonFn{bvh.prim_lo.data(), bvh.prim_hi.data(), bvh.centroid_box.data(), bits,
                              bvh.morton.data(), bvh.prim_iota.data(), face_group, subset, pieces});
  exec.sort_pairs(bvh.morton.data(), bvh.morton_sorted.data(), bvh.prim_iota.data(),
                  bvh.leaf_prim.data(), n, static_cast<int>(bits), bvh.temp.data(),
                  bvh.temp.size());
  exec.for_each_n(n, GatherLeafBoxesFn{bvh.leaf_prim.data(), bvh.prim_lo.data(), bvh.prim_hi.data(),
                                       bvh.leaf_box.data()});
  if (subset.faces) exec.for_each_n(n, SubsetLeafPrimFn{subset, bvh.leaf_prim.data()});
  if (n == 1) return;
  exec.fill(bvh.other_bound.data(), n - 1, kNoNode);
  exec.fill(bvh.count_log.data(), size_t(n) + 1, 0u);
  exec.for_each_n(n, ApetreiBuildFn{apetrei_tree(bvh, bvh.morton_sorted.data()), n},
                  Balance::uneven);
}

// Rebuilds the hierarchy over a subset of the mesh's faces: boxes, Morton codes, radix
// sort, Apetrei build. Leaves end up sorted, holding mesh face indices; internal nodes are
// in build order until order_depth_first runs. With `face_group` (per mesh face, < 2^6)
// each group's faces form their own subtrees (MortonFn): a tree that is only refitted
// while its groups move apart (rigid objects) loosens only the few nodes above them; with
// `pieces` (PieceOrder) so do the mesh's connected pieces.
template <class Exec>
void build_hierarchy(Exec& exec, Lbvh<Exec>& bvh, const MeshView& mesh, MortonBits bits,
                     FaceSubset subset, const uint32_t* face_group = nullptr, PieceOrder pieces = {}) {
  build_boxes(exec, bvh, mesh, subset);
  build_from_boxes(exec, bvh, bits, subset, face_group, pieces);
}

// The hierarchy over all of the mesh's faces.
template <class Exec>
void build_hierarchy(Exec& exec, Lbvh<Exec>& bvh, const MeshView& mesh, MortonBits bits) {
  build_hierarchy(exec, bvh, mesh, bits, FaceSubset{nullptr, mesh.num_faces});
}

}  // namespace cdb
