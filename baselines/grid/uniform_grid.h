#pragma once
// Uniform-grid baseline in the spirit of OTG (Wang, Lin, Zhang, Tang 2014), issue 6. Per
// frame, on either executor: triangle boxes; the cell size and levels from the boxes'
// statistics (grid_geometry.h); every box registered in each cell of its level that it
// overlaps; the (cell key, box) entries radix-sorted by key; pair tests per cell, each
// pair reported once (cell_pairs.h).
//
// One host synchronization a frame. The sort needs its length and key bits on the host,
// and both depend on this frame's boxes; rather than read them back before the sort (the
// hash baseline's second synchronization), the host plans them from the last frame's
// values (entries + 1/4, key bits + 1), the device computes the real ones, and they come
// back with the pair count in the frame's one read-back. If they exceed the plan, the frame
// is re-run with the measured need (counted as a re-run; a larger entry array is a logged
// growth). Entries past the plan are counted, never written; nothing is truncated.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "baselines/common/cell_boxes.h"
#include "cdbench/core/error.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/memory.h"
#include "cdbench/exec/tuning.h"
#include "cdbench/geometry/mesh.h"
#include "baselines/grid/cell_pairs.h"
#include "baselines/grid/grid_geometry.h"
#include "baselines/grid/grid_registration.h"

namespace cdb {

// What the device reports for the host's plan (UniformGrid::settle): the cell entries and
// the key bits the sort needs.
struct GridTotals {
  unsigned long long entries;
  unsigned long long key_bits;
};

template <class Exec>
struct UniformGrid : CellBoxes<Exec> {
  // Before the first frame's count: kEntriesPerBoxEstimate cells per box (exec/tuning.h);
  // frame 0 re-runs if it is short.
  // Entries are indexed with 32 bits.
  static constexpr size_t kMaxPlan = 0xffffffffull;

  explicit UniformGrid(Exec& exec) : CellBoxes<Exec>(exec, "grid") {
    bind_arrays(exec.memory(), "grid.",
                {{&level, "level"}, {&level_begin, "level_begin"}, {&trimmed, "trimmed"}, {&params, "params"},
                 {&totals, "totals"}, {&keys, "keys"}, {&sorted_keys, "sorted_keys"}, {&boxes, "boxes"},
                 {&sorted_boxes, "sorted_boxes"}});
  }

  void reserve(Exec& exec, uint32_t n) {
    this->reserve_boxes(n);
    level.reserve(n);
    level_begin.reserve(kGridMaxLevels + 1);
    trimmed.reserve(1);
    params.reserve(1);
    totals.reserve(1);
    num_boxes = n;
    planned_entries = std::clamp<size_t>(kEntriesPerBoxEstimate * size_t(n), 1024, kMaxPlan);
    key_bits = 3 * kCellAxisBits + 1;
    reserve_entries(exec, planned_entries);
  }

  void reserve_entries(Exec& exec, size_t entries) {
    for (auto* a : {&keys, &sorted_keys}) a->reserve(entries);
    for (auto* a : {&boxes, &sorted_boxes}) a->reserve(entries);
    size_t t = std::max(exec.sort_temp_bytes(entries), this->box_temp_bytes(exec, num_boxes));
    t = std::max(t, exec.template reduce_temp_bytes_of<TrimmedWidths>(num_boxes));
    t = std::max(t, exec.template reduce_temp_bytes_of<unsigned long long>(num_boxes));
    this->temp.reserve(t);
  }

  // After the frame's read-back of the device totals: whether the last build's plan held
  // them. Either way, plans the next build (this frame's re-run, or the next frame) from
  // them; the build grows the entry arrays (logged) if the plan exceeds them.
  bool settle(const GridTotals& t) {
    const unsigned long long entries = t.entries, bits = t.key_bits;
    if (entries > kMaxPlan)
      fail("grid: " + std::to_string(entries) + " cell entries exceed 32-bit offsets");
    planned_entries = std::clamp<size_t>(size_t(entries + entries / 4), 1024, kMaxPlan);
    key_bits = static_cast<int>(std::min<unsigned long long>(64, bits + 1));
    return entries <= built_entries && bits <= uint64_t(built_key_bits);
  }

  // The kernels' view, for a build or its pair tests with `planned` entries.
  GridArrays arrays(uint32_t planned) {
    return {this->lo.data(),     this->hi.data(),     params.data(), this->counts.data(),
            this->offsets.data(), level.data(),        level_begin.data(), keys.data(),
            sorted_keys.data(),  boxes.data(),        sorted_boxes.data(), &totals.data()->entries,
            planned};
  }

  Array<uint32_t> level, level_begin;
  Array<TrimmedWidths> trimmed;
  Array<GridLayout> params;
  Array<GridTotals> totals;
  Array<uint64_t> keys, sorted_keys;
  Array<uint32_t> boxes, sorted_boxes;
  uint32_t num_boxes = 0;
  // The host's plan for the next build's sort (its length and key bits), and the plan the
  // last build ran with, which its pair tests use.
  size_t planned_entries = 0;
  int key_bits = 64;
  size_t built_entries = 0;
  int built_key_bits = 64;
};

// Cell size and levels, registration, sort: no host synchronization.
template <class Exec>
void grid_build(Exec& exec, UniformGrid<Exec>& g, uint32_t n) {
  if (n == 0) {
    exec.fill(g.totals.data(), 1, GridTotals{0, 0});
    return;
  }
  if (g.planned_entries > g.keys.capacity()) g.reserve_entries(exec, g.planned_entries);
  g.built_entries = g.planned_entries;
  g.built_key_bits = g.key_bits;
  const uint32_t planned = static_cast<uint32_t>(g.built_entries);
  reduce_scene_stats(exec, g, n);
  exec.reduce(n, TrimmedWidthsFn{g.lo.data(), g.hi.data(), g.scene.data(), n}, TrimmedWidthsOp{},
              TrimmedWidths{0.0, 0ull}, g.trimmed.data(), g.temp.data(), g.temp.size());
  unsigned long long* entries = &g.totals.data()->entries;
  exec.for_each_n(1, GridLayoutFn{g.scene.data(), g.trimmed.data(), g.params.data(), &g.totals.data()->key_bits});
  const GridArrays arrays = g.arrays(planned);
  exec.for_each_n(n, GridCountFn{arrays});
  exec.reduce(n, EntryTotalFn{g.counts.data()}, SumOp{}, 0ull, entries, g.temp.data(), g.temp.size());
  exec.exclusive_scan(g.counts.data(), g.offsets.data(), n, g.temp.data(), g.temp.size());
  exec.for_each_n(n, GridFillFn{arrays});
  const int bits = g.built_key_bits;
  const uint64_t pad_key = bits >= 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1;
  exec.for_each_n(planned, GridPadFn{arrays, pad_key});
  exec.sort_pairs(g.keys.data(), g.sorted_keys.data(), g.boxes.data(), g.sorted_boxes.data(),
                  planned, bits, g.temp.data(), g.temp.size());
  exec.for_each_n(kGridMaxLevels + 1, LevelBeginFn{arrays});
}

template <class Exec>
void grid_pairs(Exec& exec, UniformGrid<Exec>& g, uint32_t n, const PairSink& sink) {
  if (n == 0) return;
  const uint32_t planned = static_cast<uint32_t>(g.built_entries);
  const GridArrays arrays = g.arrays(planned);
  exec.for_each_staged(planned, SameLevelPairsFn{{sink}, arrays}, Balance::uneven);
  exec.for_each_staged(n, CoarserLevelPairsFn{{sink}, arrays}, Balance::uneven);
}

}  // namespace cdb
