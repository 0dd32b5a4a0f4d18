#pragma once
// EXAMPLE, not a tuned baseline: the textbook sort-and-sweep along x, written once over
// the executor, as docs/extending.md walks through it. Per frame: every triangle's box;
// the triangles sorted by their box's minimum x; then one thread per sorted box walks
// forward through the boxes that start before it ends along x, testing each for full 3D
// overlap. The tuned baseline (baselines/sweep/sweep.h) picks the axis of largest spread
// and gathers the boxes into sorted order; this one reads them through the order.
//
// Exact for closed boxes: if boxes a and b overlap and a sorts first, lo_x(a) <= lo_x(b)
// <= hi_x(a), and every box sorted between them starts no later than b does, so a's walk
// reaches b. Each pair is found once, from the earlier of its two boxes.
#include <cstddef>
#include <cstdint>

#include "core/aabb.h"
#include "core/float_bits.h"
#include "core/pair_sink.h"
#include "exec/balance.h"
#include "exec/memory.h"
#include "geometry/mesh.h"

namespace cdb {

// A float as an unsigned key of the same order, for the executor's radix sort: positives
// get the sign bit set, negatives all bits flipped. -0 sorts before +0; they compare equal
// as floats, which is all the walk's stop test looks at.
CDB_HD_INLINE uint64_t example_sort_key(float x) {
  const uint32_t bits = float_bits(x);
  return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

struct ExampleKeyFn {
  const vec4f* lo;
  uint64_t* keys;
  uint32_t* faces;
  CDB_HD void operator()(uint32_t f) const {
    keys[f] = example_sort_key(lo[f].x);
    faces[f] = f;
  }
};

// One thread per position s of the sorted order.
struct ExampleSweepFn {
  uint32_t n;
  const uint32_t* order;  // faces by ascending minimum x
  const vec4f* lo;        // by face
  const vec4f* hi;
  PairSink sink;
  CDB_HD void operator()(uint32_t s) const {
    const uint32_t a = order[s];
    const vec4f alo = lo[a], ahi = hi[a];
    for (uint32_t t = s + 1; t < n; ++t) {
      const uint32_t b = order[t];
      const vec4f blo = lo[b];
      if (blo.x > ahi.x) break;  // b and every later box start past a's end
      if (overlaps(alo, ahi, blo, hi[b])) sink.emit(a, b);
    }
  }
};

// The method's buffers, bound to the executor's memory and sized once from the triangle
// count (set_topology); frames only fill them.
template <class Exec>
struct ExampleSapWorkspace {
  explicit ExampleSapWorkspace(Exec& exec) {
    MemoryResource& mr = exec.memory();
    lo.bind(mr, "example-sap.lo");
    hi.bind(mr, "example-sap.hi");
    keys.bind(mr, "example-sap.keys");
    sorted_keys.bind(mr, "example-sap.sorted_keys");
    faces.bind(mr, "example-sap.faces");
    order.bind(mr, "example-sap.order");
    temp.bind(mr, "example-sap.temp");
  }

  void reserve(Exec& exec, uint32_t n) {
    lo.reserve(n);
    hi.reserve(n);
    keys.reserve(n);
    sorted_keys.reserve(n);
    faces.reserve(n);
    order.reserve(n);
    temp.reserve(exec.sort_temp_bytes(n));  // the sort's scratch, queried CUB style
  }

  Array<vec4f> lo, hi;
  Array<uint64_t> keys, sorted_keys;
  Array<uint32_t> faces, order;
  Array<std::byte> temp;
};

// The triangles' boxes (geometry/mesh.h face_box: every box option applies).
template <class Exec>
void example_sap_boxes(Exec& exec, ExampleSapWorkspace<Exec>& w, const MeshView& mesh) {
  exec.for_each_n(mesh.num_faces, FaceBoxFn{mesh, w.lo.data(), w.hi.data()});
}

template <class Exec>
void example_sap_sort(Exec& exec, ExampleSapWorkspace<Exec>& w, uint32_t n) {
  if (n == 0) return;
  exec.for_each_n(n, ExampleKeyFn{w.lo.data(), w.keys.data(), w.faces.data()});
  exec.sort_pairs(w.keys.data(), w.sorted_keys.data(), w.faces.data(), w.order.data(), n, 32,
                  w.temp.data(), w.temp.size());
}

// Walks are as long as the boxes they overlap along x: uneven work.
template <class Exec>
void example_sap_pairs(Exec& exec, const ExampleSapWorkspace<Exec>& w, uint32_t n, const PairSink& sink) {
  exec.for_each_n(n, ExampleSweepFn{n, w.order.data(), w.lo.data(), w.hi.data(), sink}, Balance::uneven);
}

}  // namespace cdb
