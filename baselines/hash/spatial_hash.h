#pragma once
// Spatial-hashing baseline in the spirit of kDet (issue 6). Per frame: triangle boxes; a
// uniform grid whose cell size is the mean box extent (a device reduction); every box
// registered in each cell it overlaps (count, exclusive scan, fill); entries sorted by the
// hash bucket of their cell; all pairs of boxes within a bucket tested.
//
// Exactness rests on the cell baselines' one monotone cell coordinate (common/cell_coord.h),
// used for registration and for the ownership rule (common/home_cell.h): a pair is
// reported only in its home cell, from the two entries whose real cell (stored with the
// entry, not just its bucket) is that cell. Buckets shared by different cells (hash
// collisions) therefore cost work, never duplicates. Coordinates are clamped to the grid,
// which keeps the coordinate monotone (cells at the border merge; nothing is lost).
//
// A box covering more than kMaxCellsPerBox cells is not registered; it is "large" and is
// tested against every box directly. When more than kMaxLargeBoxes are large (or the
// entries would not fit 32-bit offsets), the cell size is quadrupled and the counting
// re-run: a coarser grid is slower, never wrong.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "baselines/common/cell_boxes.h"
#include "cdbench/exec/tuning.h"
#include "baselines/common/cell_coord.h"
#include "baselines/common/cell_range.h"
#include "baselines/common/home_cell.h"
#include "baselines/common/staged_pairs.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/atomics.h"
#include "cdbench/core/error.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/gather.h"
#include "cdbench/exec/memory.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

inline constexpr uint64_t kMaxCellsPerBox = 64;
inline constexpr uint32_t kMaxLargeBoxes = 32;

// One thread: cell size = mean box width times `scale`, but at least 2^-20 of the scene's
// largest extent (so the grid fits the packed coordinates) and positive.
struct HashLatticeFn {
  const SceneStats* scene;
  uint32_t n;
  double scale;
  CellLattice<float>* lattice;
  CDB_HD void operator()(uint32_t) const {
    const SceneStats s = *scene;
    double cell = max_of(s.width_sum / n, scene_extent(s) / double(1u << kCellAxisBits)) * scale;
    if (!(cell > 0.0)) cell = 1.0;
    const double inv = 1.0 / cell;
    CellLattice<float> g;
    for (int k = 0; k < 3; ++k) g.origin[k] = s.lo[k];
    g.inv_cell = float(min_of(inv, double(std::numeric_limits<float>::max())));
    *lattice = g;
  }
};

CDB_HD_INLINE uint64_t pack_cell(const CellCoords& c) {
  return uint64_t(c.x) | (uint64_t(c.y) << kCellAxisBits) | (uint64_t(c.z) << (2 * kCellAxisBits));
}

// Bucket of a cell: the top `bits` bits of a 64-bit mix (MurmurHash3's finalizer).
CDB_HD_INLINE uint64_t cell_bucket(uint64_t cell, uint32_t bits) {
  uint64_t h = cell;
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h >> (64 - bits);
}

// The hash's arrays as its kernels see them (SpatialHash::arrays): one plain view, passed
// by value, instead of each kernel naming the pointers it reads one by one.
struct HashArrays {
  const vec4f *lo, *hi;               // the face boxes
  const CellLattice<float>* lattice;  // the cell size of the grid tried
  // Per box: its cell entries (0 for a large box), the offset of its first; the large boxes
  // and their count.
  uint32_t *counts, *offsets, *large, *large_count;
  // The entries: bucket keys and ids as registered and sorted, each one's box and real cell.
  uint64_t *keys, *sorted_keys;
  uint32_t *entry_ids, *sorted_ids, *entry_box, *sorted_box;
  uint64_t *entry_cell, *sorted_cell;
};

// Per box: how many cells it covers, or 0 and a place in the large list.
struct CountCellsFn {
  HashArrays h;  // writes counts, large and large_count
  CDB_HD void operator()(uint32_t i) const {
    const uint64_t cells = cell_range(*h.lattice, h.lo[i], h.hi[i]).cells();
    if (cells > kMaxCellsPerBox) {
      h.counts[i] = 0;
      h.large[atomic_add_relaxed(h.large_count, 1u)] = i;
    } else {
      h.counts[i] = static_cast<uint32_t>(cells);
    }
  }
};

// What the host reads back once per grid: entries to allocate and sort, and large boxes.
struct EntryTotals {
  unsigned long long entries;
  uint32_t large;
};

struct EntryTotalsOp {
  CDB_HD EntryTotals operator()(const EntryTotals& a, const EntryTotals& b) const {
    return {a.entries + b.entries, a.large + b.large};
  }
};

struct EntryTotalsFn {
  const uint32_t* counts;
  CDB_HD EntryTotals operator()(uint32_t i) const {
    const uint32_t c = counts[i];
    return {c, c == 0 ? 1u : 0u};
  }
};

struct FillCellsFn {
  HashArrays h;  // writes keys, entry_ids, entry_box and entry_cell
  uint32_t bucket_bits;
  CDB_HD void operator()(uint32_t i) const {
    if (h.counts[i] == 0) return;
    uint32_t e = h.offsets[i];
    for_each_cell(cell_range(*h.lattice, h.lo[i], h.hi[i]), [&](CellCoords c) {
      const uint64_t cell = pack_cell(c);
      h.keys[e] = cell_bucket(cell, bucket_bits);
      h.entry_ids[e] = e;
      h.entry_box[e] = i;
      h.entry_cell[e++] = cell;
      return true;
    });
  }
};

// One thread per sorted entry: the later entries of its bucket that lie in the same real
// cell; a pair is reported only in its home cell.
struct PairsInCellsFn : StagedPairs {
  HashArrays h;
  uint32_t entries;
  CDB_HD void operator()(uint32_t k, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const uint64_t* buckets = h.sorted_keys;
    const uint64_t* cell = h.sorted_cell;
    const uint64_t bucket = buckets[k], c = cell[k];
    const CellLattice<float> g = *h.lattice;
    emit_later_in_cell(
        k, entries, h.sorted_box, h.lo, h.hi, [&](uint32_t t) { return buckets[t] == bucket; },
        [&](uint32_t t) { return cell[t] == c; },
        [&](const vec4f& alo, const vec4f& blo) { return pack_cell(home_cell(g, alo, blo)) == c; }, out);
  }
};

// One thread per box: against every large box. A pair of two large boxes is reported by
// the thread of the larger index only.
struct LargePairsFn : StagedPairs {
  HashArrays h;
  CDB_HD void operator()(uint32_t j, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const uint32_t count = *h.large_count;
    const bool j_large = h.counts[j] == 0;
    const vec4f jlo = h.lo[j], jhi = h.hi[j];
    for (uint32_t q = 0; q < count; ++q) {
      const uint32_t a = h.large[q];
      if (a == j || (j_large && j < a)) continue;
      if (overlaps(jlo, jhi, h.lo[a], h.hi[a])) out.emit(a, j);
    }
  }
};

// Workspace of the hash: per-box arrays sized from the triangle count, per-entry arrays
// from an estimate of entries per box; growth beyond either is logged and counted.
template <class Exec>
struct SpatialHash : CellBoxes<Exec> {
  explicit SpatialHash(Exec& exec) : CellBoxes<Exec>(exec, "hash") {
    bind_arrays(exec.memory(), "hash.",
                {{&large, "large"}, {&large_count, "large_count"}, {&lattice, "lattice"}, {&totals, "totals"},
                 {&keys, "keys"}, {&sorted_keys, "sorted_keys"}, {&entry_ids, "entry_ids"},
                 {&sorted_ids, "sorted_ids"}, {&entry_box, "entry_box"}, {&sorted_box, "sorted_box"},
                 {&entry_cell, "entry_cell"}, {&sorted_cell, "sorted_cell"}});
  }

  void reserve(Exec& exec, uint32_t n) {
    this->reserve_boxes(n);
    large.reserve(n);
    large_count.reserve(1);
    lattice.reserve(1);
    totals.reserve(1);
    reserve_entries(exec, n, std::max<size_t>(1024, kEntriesPerBoxEstimate * n));
  }

  void reserve_entries(Exec& exec, uint32_t n, size_t entries) {
    for (auto* a : {&keys, &sorted_keys, &entry_cell, &sorted_cell}) a->reserve(entries);
    for (auto* a : {&entry_ids, &sorted_ids, &entry_box, &sorted_box}) a->reserve(entries);
    size_t t = std::max(exec.sort_temp_bytes(entries), this->box_temp_bytes(exec, n));
    t = std::max(t, exec.template reduce_temp_bytes_of<EntryTotals>(n));
    this->temp.reserve(t);
  }

  HashArrays arrays() {
    return {this->lo.data(),   this->hi.data(),     lattice.data(),    this->counts.data(), this->offsets.data(),
            large.data(),      large_count.data(),  keys.data(),       sorted_keys.data(),  entry_ids.data(),
            sorted_ids.data(), entry_box.data(),    sorted_box.data(), entry_cell.data(),   sorted_cell.data()};
  }

  Array<uint32_t> large, large_count;
  Array<CellLattice<float>> lattice;
  Array<EntryTotals> totals;
  Array<uint64_t> keys, sorted_keys;
  Array<uint32_t> entry_ids, sorted_ids, entry_box, sorted_box;
  Array<uint64_t> entry_cell, sorted_cell;
  // Set by hash_build for hash_pairs.
  uint32_t num_entries = 0, num_large = 0;
};

// Grid, registration, sort. Reads the entry totals back once per grid tried; returns how
// many times the cell size had to grow.
template <class Exec>
uint32_t hash_build(Exec& exec, SpatialHash<Exec>& h, uint32_t n) {
  h.num_entries = h.num_large = 0;
  if (n == 0) return 0;
  reduce_scene_stats(exec, h, n);
  uint32_t regrids = 0;
  double scale = 1.0;
  EntryTotals totals{};
  for (;;) {
    exec.for_each_n(1, HashLatticeFn{h.scene.data(), n, scale, h.lattice.data()});
    exec.fill(h.large_count.data(), 1, 0u);
    exec.for_each_n(n, CountCellsFn{h.arrays()});
    exec.reduce(n, EntryTotalsFn{h.counts.data()}, EntryTotalsOp{}, EntryTotals{},
                h.totals.data(), h.temp.data(), h.temp.size());
    exec.copy_to_host(&totals, h.totals.data(), 1);
    if (totals.large <= kMaxLargeBoxes && totals.entries <= std::numeric_limits<uint32_t>::max())
      break;
    // Each step quadruples the cell; after enough of them the whole scene fits a few cells,
    // so this only fails on a scene that no 32-bit entry count can hold.
    if (++regrids > 64) fail("hash: no cell size keeps the grid within 2^32 entries");
    scale *= 4.0;
  }
  const uint32_t entries = static_cast<uint32_t>(totals.entries);
  h.num_entries = entries;
  h.num_large = totals.large;
  // Against what the buffers were last sized for, not their capacity: a new pass's reserve()
  // sizes the sort's temporary storage for the estimate again while the arrays keep the
  // capacity an earlier pass grew them to.
  if (entries > h.keys.size()) h.reserve_entries(exec, n, entries + entries / 4);
  exec.exclusive_scan(h.counts.data(), h.offsets.data(), n, h.temp.data(), h.temp.size());
  uint32_t bits = 1;
  while (bits < 32 && (uint64_t(1) << bits) < 2 * uint64_t(entries)) ++bits;
  // After reserve_entries, which may have moved the entry arrays.
  exec.for_each_n(n, FillCellsFn{h.arrays(), bits});
  exec.sort_pairs(h.keys.data(), h.sorted_keys.data(), h.entry_ids.data(), h.sorted_ids.data(),
                  entries, static_cast<int>(bits), h.temp.data(), h.temp.size());
  gather(exec, entries, h.sorted_ids.data(), h.entry_box.data(), h.entry_cell.data(), h.sorted_box.data(),
         h.sorted_cell.data());
  return regrids;
}

template <class Exec>
void hash_pairs(Exec& exec, SpatialHash<Exec>& h, uint32_t n, const PairSink& sink) {
  exec.for_each_staged(h.num_entries,
                  PairsInCellsFn{{sink}, h.arrays(), h.num_entries},
                  Balance::uneven);
  if (h.num_large > 0)
    exec.for_each_staged(n, LargePairsFn{{sink}, h.arrays()});
}

}  // namespace cdb
