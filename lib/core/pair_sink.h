#pragma once
#include "cdbench/core/append_stage.h"
#include "cdbench/core/atomics.h"
#include "cdbench/core/pair.h"

namespace cdb {

CDB_HD_INLINE bool share_vertex(const uint32_t* a, const uint32_t* b) {
  return a[0] == b[0] || a[0] == b[1] || a[0] == b[2] || a[1] == b[0] || a[1] == b[1] ||
         a[1] == b[2] || a[2] == b[0] || a[2] == b[1] || a[2] == b[2];
}

// Where a query writes its pairs: a counter and a buffer of fixed capacity. Every pair is
// counted; pairs past the capacity are not stored, and the caller, seeing count >
// capacity after the kernel, grows the buffer (counted) and runs the query again.
// Nothing is ever truncated silently.
//
// Co-vertex filtering (--skip-adjacent): given the faces' vertex indices (3 per face), pairs
// of triangles that share a vertex are dropped here, after the overlap test, so every
// query and baseline filters the same way and traversal (fronts) is unchanged.
struct PairSink {
  PrimPair* out;
  unsigned long long* count;
  unsigned long long capacity;
  const uint32_t* skip_adjacent_faces = nullptr;
  // Declared queries (geometry/objects.h): per face its object, per object its partners.
  const uint32_t* face_object = nullptr;
  const uint64_t* partners = nullptr;
  // The block's stage in shared memory (core/append_stage.h), set inside a staged kernel;
  // null: append directly.
  PairStage* stage = nullptr;

  CDB_HD_INLINE PairSink staged(PairStage* s) const {
    PairSink p = *this;
    p.stage = s;
    return p;
  }

  CDB_HD_INLINE void emit(uint32_t i, uint32_t j) const {
    if (face_object && !((partners[face_object[i]] >> face_object[j]) & 1u)) return;
    if (skip_adjacent_faces && share_vertex(skip_adjacent_faces + 3 * size_t(i),
                                            skip_adjacent_faces + 3 * size_t(j)))
      return;
    const PrimPair p = make_pair_ordered(i, j);
    if (stage && stage->put(p)) return;
    const unsigned long long slot = claim_one(count);
    if (slot < capacity) out[slot] = p;
  }

#if defined(__CUDACC__)
  // Every thread of a staged kernel's block, after its last emit (and a barrier).
  __device__ void flush(PairStage& s) const { s.flush(count, out, capacity); }
#endif
};

}  // namespace cdb
