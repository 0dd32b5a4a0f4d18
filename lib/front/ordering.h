#pragma once
// Histogram sort of a front by its BVH node key j (paper §3.3): count log (filled while the
// front was produced) -> exclusive scan -> offset log -> one scatter. Within the segment of
// node j, sprout-marked nodes (1) fill from the back and prune-marked (0) from the front, so
// nodes that will take the same branch sit together. No comparison sort.
#include <cstddef>
#include <cstdint>

#include "cdbench/core/atomics.h"
#include "cdbench/front/front.h"

namespace cdb {

// Places front nodes in the segments of an offset log: a node of BVH node j goes to j's
// segment, sprout-marked from its back and prune-marked from its front (the cursors count
// the places taken on each side; zero before the pass).
struct SegmentScatter {
  uint32_t* offset_log;  // the count log's exclusive scan, written before the scatter
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

// Where the second run of a generate or an update puts its front nodes: each straight at its
// sorted place, by the offset log that the first run's count log was scanned into (the
// operation runs the same traversals each time, so it meets the same nodes). A front
// produced this way needs no unordered copy to scatter from (FrontQuery::produce_placed).
// Within node j's segment, sprout-marked nodes fill from the back and prune-marked from the
// front, as SegmentScatter places them. A kind whose first run counted more nodes than its
// arrays hold places nothing: the caller grows them and runs the operation again.
struct PlacedFrontSink {
  const uint32_t* offset_log[2];
  uint32_t* cursor_front[2];
  uint32_t* cursor_back[2];
  uint32_t* prim[2];
  uint32_t* node[2];
  const unsigned long long* count;  // count[kind]: the first run's
  unsigned long long capacity[2];

  CDB_HD_INLINE PlacedFrontSink staged(FrontStage*) const { return *this; }
  // The kind's arrays are picked by selects (FrontSink::push says why).
  CDB_HD_INLINE void push(uint32_t i, uint32_t ref, uint8_t m) const {
    const bool ext = is_leaf(ref);
    if (count[ext ? 1 : 0] > (ext ? capacity[1] : capacity[0])) return;
    const uint32_t key = ref_index(ref);
    const uint32_t* log = ext ? offset_log[1] : offset_log[0];
    const uint32_t pos = m ? log[key + 1] - 1 - claim_one(&(ext ? cursor_back[1] : cursor_back[0])[key])
                           : log[key] + claim_one(&(ext ? cursor_front[1] : cursor_front[0])[key]);
    (ext ? prim[1] : prim[0])[pos] = i;
    (ext ? node[1] : node[0])[pos] = ref;
  }
#if defined(__CUDACC__)
  __device__ void flush(FrontStage&) const {}
#endif
};

// Whether every append of a frame so far fit its buffer: the pairs and the fronts each
// query produced, as counted on the device (each count may exceed its capacity: the frame
// then grows the buffer and runs again). A scatter into a current front runs only when all
// fit, so that a frame which runs again finds its current fronts untouched. Every thread
// reads the same few counts: one cached load each.
struct FrameFit {
  static constexpr uint32_t kMax = 8;  // the pairs and two kinds of each of three queries, with room
  const unsigned long long* count[kMax];
  unsigned long long capacity[kMax];
  uint32_t n = 0;
  void add(const unsigned long long* c, unsigned long long cap) {
    count[n] = c;
    capacity[n] = cap;
    ++n;
  }
  CDB_HD_INLINE bool fits() const {
    for (uint32_t k = 0; k < n; ++k)
      if (*count[k] > capacity[k]) return false;
    return true;
  }
};

struct ScatterFrontFn {
  const unsigned long long* count;  // produced front size (device), may exceed capacity
  unsigned long long capacity;      // past it the front is being regrown: scatter nothing
  const uint32_t* prim;
  const uint32_t* node;
  const uint8_t* mark;
  SegmentScatter to;
  FrameFit fit{};  // the frame's other appends, where the scatter overwrites a current front
  CDB_HD void operator()(uint32_t e) const {
    const unsigned long long n = *count;
    if (n > capacity || e >= n || !fit.fits()) return;
    to.place(prim[e], node[e], mark[e] != 0);
  }
};

// One launch over both kinds of a front: index e < n0 runs `internal`, the rest `external`,
// each pass launched over its own kind's size or capacity. A front's ordering passes are
// short, so a launch each for the two kinds cost as much again as the work.
template <class F>
struct BothKinds {
  F internal, external;
  uint32_t n0;
  CDB_HD void operator()(uint32_t e) const {
    if (e < n0)
      internal(e);
    else
      external(e - n0);
  }
};

// Runs `internal` over n_internal indices and `external` over n_external in one launch.
template <class Exec, class F>
void for_both_kinds(Exec& exec, const F& internal, size_t n_internal, const F& external, size_t n_external) {
  exec.for_each_n(n_internal + n_external, BothKinds<F>{internal, external, uint32_t(n_internal)});
}

// A scatter by front f's offset log into `prim` and `node` (f's current arrays, or its raw
// ones for balance). Its cursors must be zero: the fill of f's order counts before the front
// was produced zeroed them with the count log (FrontQuery::produce_sink), or zero_cursors did.
template <class Exec>
SegmentScatter segment_scatter(FrontArrays<Exec>& f, Array<uint32_t>& prim, Array<uint32_t>& node) {
  return {f.offset_log.data(), f.cursor_front(), f.cursor_back(), prim.data(), node.data()};
}

// Zeroes f's cursors (both sides, one fill) for a scatter of a front that was not just
// produced (balance).
template <class Exec>
void zero_cursors(Exec& exec, FrontArrays<Exec>& f) {
  exec.fill(f.cursor_front(), 2 * f.segments(), 0u);
}

}  // namespace cdb
