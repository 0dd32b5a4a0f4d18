#pragma once
// BVTT fronts for self-collision (paper §3.3, Alg. 1). front(i, j) pairs a query leaf i
// (Morton order) with a BVH node j. For each leaf i, the nodes j of its front partition the
// leaves (i, N-1]: they are where the leaf algorithm stopped descending (a leaf, or an
// internal node whose box missed leaf i's). Because they partition that range, any
// traversal started from them under refit reports exactly the pairs of leaf i.
// Fronts are stored apart by the kind of j: the internal front (j internal) and the
// external front (j a leaf), SoA.
#include <cstdint>
#include <string>
#include <utility>

#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/append_stage.h"
#include "cdbench/core/atomics.h"
#include "cdbench/exec/memory.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

enum FrontKind : int { kInternalFront = 0, kExternalFront = 1 };

// Counts that every block of a launch adds to are spread over kStopSlots slots
// (exec/tuning.h; pipeline/front_counters.h): block b adds to slot b % kStopSlots.

CDB_HD_INLINE int front_kind(uint32_t ref) { return is_leaf(ref) ? kExternalFront : kInternalFront; }

// A front node's BVH node once it is dropped where it lies: by an update in place (its
// replacements were appended, or it climbed into another node) or by the classification of
// a restructure. Every operation that reads a front skips it.
inline constexpr uint32_t kFrontDropped = kNoNode;

// Where an operation appends the fronts it produces: per kind a counter (every push
// counted, pushes past capacity not stored: the caller grows and re-runs), and, for ordered
// pipelines, the count log of the histogram sort (front nodes per BVH node j).
struct FrontSink {
  uint32_t* prim[2];
  uint32_t* node[2];
  uint8_t* mark[2];
  unsigned long long* count;  // count[kind]
  unsigned long long capacity[2];
  uint32_t* count_log[2];     // null for unordered fronts
  // The block's stage in shared memory (core/append_stage.h), set inside a staged kernel;
  // null: append directly.
  FrontStage* stage = nullptr;

  CDB_HD_INLINE FrontSink staged(FrontStage* s) const {
    FrontSink f = *this;
    f.stage = s;
    return f;
  }

  // mark: 1 = produced by sprouting, 0 = kept by pruning (the paper's opt mark).
  // The kind's arrays are picked by selects, never by indexing with the kind: a copy of the
  // sink (staged() makes one per kernel) indexed by a value known only at run time lives in
  // local memory, and the update's kernel then kept a 192-byte stack frame that every push
  // read (ptxas -v).
  CDB_HD_INLINE void push(uint32_t i, uint32_t ref, uint8_t m) const {
    const bool ext = is_leaf(ref);
    const int k = ext ? kExternalFront : kInternalFront;
    if (uint32_t* log = ext ? count_log[1] : count_log[0]) count_one(&log[ref_index(ref)]);
    if (stage && stage->put(k, i, ref, m)) return;
    const unsigned long long slot = claim_one(count + k);
    if (slot < (ext ? capacity[1] : capacity[0])) {
      (ext ? prim[1] : prim[0])[slot] = i;
      (ext ? node[1] : node[0])[slot] = ref;
      (ext ? mark[1] : mark[0])[slot] = m;
    }
  }

#if defined(__CUDACC__)
  // Every thread of a staged kernel's block, after its last push (and a barrier).
  __device__ void flush(FrontStage& s) const { s.flush(count, prim, node, mark, capacity); }
#endif

};

// Whether a front holds the arrays its operations produce into (the raw arrays and the
// histogram's counters) or borrows another's (FrontArrays::swap_produced), or holds no
// front arrays at all and borrows another's produced arrays as its current ones, which it
// is placed into in order (FrontQuery::produce_placed).
enum class ProducedArrays { own, lent, lent_as_current };

// One kind of front: the current front (ordered or not) and the append target of the last
// operation. The histogram sort scatters a produced front from the append target straight
// into the current arrays, but only where every append of the frame fit (ScatterFrontFn,
// FrameFit): then the frame runs no operation again and the current front, which the
// operation has read already, is dead; a frame that overflowed keeps it for its re-run.
// Balance scatters the other way and swaps the two. So a front node costs 17 bytes of
// capacity: prim and node on each side, and the produced node's mark (a third, sorted copy
// made it 25). All five arrays keep one capacity (capacity()), which the swaps rely on; a
// front that lent its produced arrays (swap_produced) has none until they come back.
template <class Exec>
struct FrontArrays {
  // `name` tells the fronts of one query apart in the growth log ("front", "inter_front").
  void bind(MemoryResource& mr, int kind, const std::string& name = "front") {
    const std::string k = name + (kind == kInternalFront ? "_internal." : "_external.");
    bind_arrays(mr, k, {{&prim, "prim"}, {&node, "node"}, {&raw_prim, "raw_prim"}, {&raw_node, "raw_node"},
                        {&raw_mark, "raw_mark"}, {&order_counts, "order_counts"}, {&offset_log, "offset_log"},
                        {&tail_counts, "tail_counts"}, {&tail_offset_log, "tail_offset_log"}});
  }
  // Capacity for front nodes (all five arrays) and segment count (BVH nodes); `tails`: the
  // counters of the tails that updates in place append (--update-in-place only). With
  // `produced` lent, only the current front and its offset log: the rest comes by
  // swap_produced.
  void reserve(size_t capacity, size_t segments, bool tails, ProducedArrays produced = ProducedArrays::own) {
    if (produced != ProducedArrays::lent_as_current)
      for (auto* a : {&prim, &node}) a->reserve(capacity);
    segments_ = segments;
    offset_log.reserve(segments + 1);
    if (produced == ProducedArrays::own) {
      for (auto* a : {&raw_prim, &raw_node}) a->reserve(capacity);
      raw_mark.reserve(capacity);
      order_counts.reserve(3 * segments + 1);
    }
    if (tails) {
      tail_counts.reserve(3 * segments + 1);
      tail_offset_log.reserve(segments + 1);
    }
  }
  size_t capacity() const {
    size_t c = raw_mark.capacity();
    for (auto* a : {&prim, &node, &raw_prim, &raw_node}) c = a->capacity() < c ? a->capacity() : c;
    return c;
  }
  // Exchanges the produced arrays (raw_*, order_counts) with `o`'s, of as many segments.
  // Between frames they hold nothing: a front that only preserves meanwhile lends them to
  // one generated beside it, whose ordering leaves its result in its current arrays.
  void swap_produced(FrontArrays& o) {
    std::swap(raw_prim, o.raw_prim);
    std::swap(raw_node, o.raw_node);
    std::swap(raw_mark, o.raw_mark);
    std::swap(order_counts, o.order_counts);
  }
  // Exchanges the produced arrays with `o`'s current ones (prim and node; with `counters`,
  // raw_mark and order_counts with `o`'s too): lent to a front that is placed into them in
  // order (ProducedArrays::lent_as_current), or, once `o`'s fronts were swapped in
  // with their counters, given back for `o`'s old current arrays.
  void swap_produced_with_current(FrontArrays& o, bool counters) {
    std::swap(raw_prim, o.prim);
    std::swap(raw_node, o.node);
    if (!counters) return;
    std::swap(raw_mark, o.raw_mark);
    std::swap(order_counts, o.order_counts);
  }
  bool has_tails() const { return tail_counts.capacity() >= 3 * segments_ + 1; }

  // The histogram sort's counters, in one buffer so that one fill zeroes them all before a
  // front is produced: the count log (front nodes per BVH node, segments + 1 entries, its
  // scan is offset_log) and the scatter's cursors (places taken from the front and from the
  // back of each node's segment).
  uint32_t* count_log() { return order_counts.data(); }
  uint32_t* cursor_front() { return order_counts.data() + segments_ + 1; }
  uint32_t* cursor_back() { return cursor_front() + segments_; }
  size_t segments() const { return segments_; }
  // The same for the tail an update in place appends (FrontQuery::patch), sorted apart.
  uint32_t* tail_count_log() { return tail_counts.data(); }
  uint32_t* tail_cursor_front() { return tail_counts.data() + segments_ + 1; }
  uint32_t* tail_cursor_back() { return tail_cursor_front() + segments_; }

  Array<uint32_t> prim, node;          // the current front
  Array<uint32_t> raw_prim, raw_node;  // produced by generate/update, unordered
  Array<uint8_t> raw_mark;
  Array<uint32_t> order_counts;  // count log and cursors (count_log(), cursor_front(), cursor_back())
  Array<uint32_t> offset_log;    // the count log's exclusive scan
  Array<uint32_t> tail_counts;      // an appended tail's count log and cursors (tail_count_log(), ...)
  Array<uint32_t> tail_offset_log;  // its scan
  size_t size = 0;  // nodes in the current front (host copy from the frame's read-back)

 private:
  size_t segments_ = 0;
};

}  // namespace cdb
