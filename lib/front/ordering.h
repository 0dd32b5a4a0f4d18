#pragma once
// Histogram sort of a front by its BVH node key j (paper §3.3): count log (filled while the
// front was produced) -> exclusive scan -> offset log -> one scatter. Within the segment of
// node j, sprout-marked nodes (1) fill from the back and prune-marked (0) from the front, so
// nodes that will take the same branch sit together. No comparison sort.
#include <cstdint>

#include "core/atomics.h"
#include "front/front.h"

namespace cdb {

struct ScatterFrontFn {
  const unsigned long long* count;  // produced front size (device), may exceed capacity
  unsigned long long capacity;      // past it the front is being regrown: scatter nothing
  const uint32_t* prim;
  const uint32_t* node;
  const uint8_t* mark;
  const uint32_t* offset_log;
  uint32_t* cursor_front;
  uint32_t* cursor_back;
  uint32_t* out_prim;
  uint32_t* out_node;
  CDB_HD void operator()(uint32_t e) const {
    const unsigned long long n = *count;
    if (n > capacity || e >= n) return;
    const uint32_t j = node[e], key = ref_index(j);
    const uint32_t pos = mark[e] ? offset_log[key + 1] - 1 - claim_one(&cursor_back[key])
                                 : offset_log[key] + claim_one(&cursor_front[key]);
    out_prim[pos] = prim[e];
    out_node[pos] = j;
  }
};

// Orders a produced front (raw arrays, size on the device in *count, at most the raw
// capacity, `launch`) into the sorted arrays, using a filled count log with `segments`
// entries.
template <class Exec>
void order_front(Exec& exec, FrontArrays<Exec>& f, size_t segments, const unsigned long long* count,
                 const uint32_t* prim, const uint32_t* node, const uint8_t* mark, size_t launch,
                 void* temp, size_t temp_bytes) {
  exec.exclusive_scan(f.count_log.data(), f.offset_log.data(), segments + 1, temp, temp_bytes);
  exec.fill(f.cursor_front.data(), segments, 0u);
  exec.fill(f.cursor_back.data(), segments, 0u);
  exec.for_each_n(launch, ScatterFrontFn{count, launch, prim, node, mark, f.offset_log.data(),
                                         f.cursor_front.data(), f.cursor_back.data(),
                                         f.sorted_prim.data(), f.sorted_node.data()});
}

}  // namespace cdb
