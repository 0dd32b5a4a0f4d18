#pragma once
// EXAMPLE, not a tuned baseline: the textbook sort-and-sweep along x, written once over
// the executor, as docs/extending.md walks through it. Per frame: every triangle's box;
// the triangles sorted by their box's minimum x; then one thread per sorted box walks
// forward through the boxes that start before it ends along x, testing each for full 3D
// overlap. The boxes and the sort are the baselines' building blocks (common/sorted_boxes.h:
// the executor's radix sort on the floats' order-preserving bits); the method's own are the
// sort's coordinate (MinX) and the walk (ExampleSweepFn). The tuned baseline (baselines/sweep/sweep.h) picks
// the axis of largest spread and gathers the boxes into sorted order; this one reads them
// through the order.
//
// Exact for closed boxes: if boxes a and b overlap and a sorts first, lo_x(a) <= lo_x(b)
// <= hi_x(a), and every box sorted between them starts no later than b does, so a's walk
// reaches b. Each pair is found once, from the earlier of its two boxes.
#include <cstdint>

#include "baselines/common/sorted_boxes.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/balance.h"

namespace cdb {

// The coordinate the boxes are sorted by: their minimum corner's x.
struct MinX {
  CDB_HD float operator()(const vec4f& lo) const { return lo.x; }
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

// Walks are as long as the boxes they overlap along x: uneven work.
template <class Exec>
void example_sap_pairs(Exec& exec, const SortedBoxes<Exec>& w, uint32_t n, const PairSink& sink) {
  exec.for_each_n(n, ExampleSweepFn{n, w.order.data(), w.lo.data(), w.hi.data(), sink}, Balance::uneven);
}

}  // namespace cdb
