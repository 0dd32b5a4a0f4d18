#pragma once
// Histogram sort of a front by its BVH node key j (paper §3.3): count log (filled while the
// front was produced) -> exclusive scan -> offset log -> one scatter. Within the segment of
// node j, sprout-marked nodes (1) fill from the back and prune-marked (0) from the front, so
// nodes that will take the same branch sit together. No comparison sort.
#include <cstdint>

#include "core/atomics.h"
#include "front/front.h"

namespace cdb {

// Places front nodes in the segments of an offset log: a node of BVH node j goes to j's
// segment, sprout-marked from its back and prune-marked from its front (the cursors count
// the places taken on each side; zero before the pass).
struct SegmentScatter {
  const uint32_t* offset_log;
  uint32_t* cursor_front;
  uint32_t* cursor_back;
  uint32_t* out_prim;
  uint32_t* out_node;
  CDB_HD_INLINE void place(uint32_t i, uint32_t j, bool sprout) const {
    const uint32_t key = ref_index(j);
    const uint32_t pos = sprout ? offset_log[key + 1] - 1 - claim_one(&cursor_back[key])
                                : offset_log[key] + claim_one(&cursor_front[key]);
    out_prim[pos] = i;
    out_node[pos] = j;
  }
};

struct ScatterFrontFn {
  const unsigned long long* count;  // produced front size (device), may exceed capacity
  unsigned long long capacity;      // past it the front is being regrown: scatter nothing
  const uint32_t* prim;
  const uint32_t* node;
  const uint8_t* mark;
  SegmentScatter to;
  CDB_HD void operator()(uint32_t e) const {
    const unsigned long long n = *count;
    if (n > capacity || e >= n) return;
    to.place(prim[e], node[e], mark[e] != 0);
  }
};

// A scatter of front f into its sorted arrays by f's offset log (`segments` entries), its
// cursors zeroed.
template <class Exec>
SegmentScatter start_segment_scatter(Exec& exec, FrontArrays<Exec>& f, size_t segments) {
  exec.fill(f.cursor_front.data(), segments, 0u);
  exec.fill(f.cursor_back.data(), segments, 0u);
  return {f.offset_log.data(), f.cursor_front.data(), f.cursor_back.data(), f.sorted_prim.data(),
          f.sorted_node.data()};
}

// Orders a produced front (raw arrays, size on the device in *count, at most the raw
// capacity, `launch`) into the sorted arrays, using a filled count log with `segments`
// entries.
template <class Exec>
void order_front(Exec& exec, FrontArrays<Exec>& f, size_t segments, const unsigned long long* count,
                 const uint32_t* prim, const uint32_t* node, const uint8_t* mark, size_t launch,
                 void* temp, size_t temp_bytes) {
  exec.exclusive_scan(f.count_log.data(), f.offset_log.data(), segments + 1, temp, temp_bytes);
  exec.for_each_n(launch, ScatterFrontFn{count, launch, prim, node, mark, start_segment_scatter(exec, f, segments)});
}

}  // namespace cdb
