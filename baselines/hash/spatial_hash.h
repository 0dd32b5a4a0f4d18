#pragma once
// Spatial-hashing baseline in the spirit of kDet (issue 6). Per frame: triangle boxes; a
// uniform grid whose cell size is the mean box extent (a device reduction); every box
// registered in each cell it overlaps (count, exclusive scan, fill); entries sorted by the
// hash bucket of their cell; all pairs of boxes within a bucket tested.
//
// Exactness rests on one monotone function, cell_coord(), used for registration and for
// the report rule. For an overlapping pair, the minimum corner m of the intersection lies
// inside both boxes, so, cell_coord being monotone, both boxes are registered in cell(m).
// The pair is reported only there: from the two entries whose real cell (stored with the
// entry, not just its bucket) equals cell(m). Buckets shared by different cells (hash
// collisions) therefore cost work, never duplicates; touching boxes (m on a cell face)
// are found in the one cell m falls into. Coordinates are clamped to the grid, which
// keeps cell_coord monotone (cells at the border merge; nothing is lost).
//
// A box covering more than kMaxCellsPerBox cells is not registered; it is "large" and is
// tested against every box directly. When more than kMaxLargeBoxes are large (or the
// entries would not fit 32-bit offsets), the cell size is quadrupled and the counting
// re-run: a coarser grid is slower, never wrong.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "core/aabb.h"
#include "core/atomics.h"
#include "core/error.h"
#include "core/pair_sink.h"
#include "exec/balance.h"
#include "exec/memory.h"
#include "geometry/mesh.h"

namespace cdb {

inline constexpr uint32_t kCellBits = 20;  // per axis: three coordinates pack into 60 bits
inline constexpr float kMaxCellCoord = float((1u << kCellBits) - 1);
inline constexpr uint64_t kMaxCellsPerBox = 64;
inline constexpr uint32_t kMaxLargeBoxes = 32;

// Scene bounds and the sum over boxes of their largest extent (in double: extents of
// 1e38-scale boxes overflow float).
struct GridStats {
  double extent_sum;
  float lo[3], hi[3];
};

struct GridStatsOp {
  CDB_HD GridStats operator()(const GridStats& a, const GridStats& b) const {
    GridStats r;
    r.extent_sum = a.extent_sum + b.extent_sum;
    for (int k = 0; k < 3; ++k) {
      r.lo[k] = min_of(a.lo[k], b.lo[k]);
      r.hi[k] = max_of(a.hi[k], b.hi[k]);
    }
    return r;
  }
  static GridStats identity() {
    const float inf = std::numeric_limits<float>::infinity();
    return {0.0, {inf, inf, inf}, {-inf, -inf, -inf}};
  }
};

struct GridStatsFn {
  const vec4f* lo;
  const vec4f* hi;
  CDB_HD GridStats operator()(uint32_t i) const {
    const vec4f a = lo[i], b = hi[i];
    const double ex = double(b.x) - double(a.x), ey = double(b.y) - double(a.y),
                 ez = double(b.z) - double(a.z);
    return {max_of(ex, max_of(ey, ez)), {a.x, a.y, a.z}, {b.x, b.y, b.z}};
  }
};

struct GridParams {
  float origin[3];
  float inv_cell;
};

// One thread: cell size = mean largest box extent times `scale`, but at least 2^-20 of the
// scene's largest extent (so the grid fits the packed coordinates) and positive.
struct GridParamsFn {
  const GridStats* stats;
  uint32_t n;
  double scale;
  GridParams* params;
  CDB_HD void operator()(uint32_t) const {
    const GridStats s = *stats;
    double scene = 0.0;
    for (int k = 0; k < 3; ++k) scene = max_of(scene, double(s.hi[k]) - double(s.lo[k]));
    double cell = max_of(s.extent_sum / n, scene / double(1u << kCellBits)) * scale;
    if (!(cell > 0.0)) cell = 1.0;
    const double inv = 1.0 / cell;
    GridParams p;
    for (int k = 0; k < 3; ++k) p.origin[k] = s.lo[k];
    p.inv_cell = float(min_of(inv, double(std::numeric_limits<float>::max())));
    *params = p;
  }
};

// The grid coordinate of x along one axis. Monotone non-decreasing in x (a rounded
// subtraction, a rounded product by a non-negative factor, a clamp, a truncation), which
// is all exactness needs. An overflow to infinity is clamped; infinity times a zero
// factor (a cell grown past float range) is NaN and maps to 0 like every other x then.
CDB_HD_INLINE uint32_t cell_coord(float x, float origin, float inv_cell) {
  const float t = (x - origin) * inv_cell;
  return t > 0.0f ? static_cast<uint32_t>(min_of(t, kMaxCellCoord)) : 0u;
}

struct CellRange {
  uint32_t lo[3], hi[3];
};

CDB_HD_INLINE CellRange cell_range(const GridParams& p, const vec4f& lo, const vec4f& hi) {
  return {{cell_coord(lo.x, p.origin[0], p.inv_cell), cell_coord(lo.y, p.origin[1], p.inv_cell),
           cell_coord(lo.z, p.origin[2], p.inv_cell)},
          {cell_coord(hi.x, p.origin[0], p.inv_cell), cell_coord(hi.y, p.origin[1], p.inv_cell),
           cell_coord(hi.z, p.origin[2], p.inv_cell)}};
}

CDB_HD_INLINE uint64_t pack_cell(uint32_t x, uint32_t y, uint32_t z) {
  return uint64_t(x) | (uint64_t(y) << kCellBits) | (uint64_t(z) << (2 * kCellBits));
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

// Per box: how many cells it covers, or 0 and a place in the large list.
struct CountCellsFn {
  const vec4f* lo;
  const vec4f* hi;
  const GridParams* params;
  uint32_t* counts;
  uint32_t* large;
  uint32_t* large_count;
  CDB_HD void operator()(uint32_t i) const {
    const CellRange r = cell_range(*params, lo[i], hi[i]);
    uint64_t cells = 1;
    for (int k = 0; k < 3; ++k) cells *= uint64_t(r.hi[k] - r.lo[k]) + 1;
    if (cells > kMaxCellsPerBox) {
      counts[i] = 0;
      large[atomic_add_relaxed(large_count, 1u)] = i;
    } else {
      counts[i] = static_cast<uint32_t>(cells);
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
  const vec4f* lo;
  const vec4f* hi;
  const GridParams* params;
  const uint32_t* counts;
  const uint32_t* offsets;
  uint32_t bucket_bits;
  uint64_t* keys;
  uint32_t* entry_ids;
  uint32_t* entry_box;
  uint64_t* entry_cell;
  CDB_HD void operator()(uint32_t i) const {
    if (counts[i] == 0) return;
    const CellRange r = cell_range(*params, lo[i], hi[i]);
    uint32_t e = offsets[i];
    for (uint32_t z = r.lo[2]; z <= r.hi[2]; ++z)
      for (uint32_t y = r.lo[1]; y <= r.hi[1]; ++y)
        for (uint32_t x = r.lo[0]; x <= r.hi[0]; ++x, ++e) {
          const uint64_t cell = pack_cell(x, y, z);
          keys[e] = cell_bucket(cell, bucket_bits);
          entry_ids[e] = e;
          entry_box[e] = i;
          entry_cell[e] = cell;
        }
  }
};

struct GatherEntriesFn {
  const uint32_t* sorted_ids;
  const uint32_t* entry_box;
  const uint64_t* entry_cell;
  uint32_t* sorted_box;
  uint64_t* sorted_cell;
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t e = sorted_ids[k];
    sorted_box[k] = entry_box[e];
    sorted_cell[k] = entry_cell[e];
  }
};

// One thread per sorted entry: the later entries of its bucket that lie in the same real
// cell; a pair is reported only in the cell of its intersection's minimum corner.
struct PairsInCellsFn {
  uint32_t entries;
  const uint64_t* buckets;
  const uint32_t* box;
  const uint64_t* cell;
  const vec4f* lo;
  const vec4f* hi;
  const GridParams* params;
  PairSink sink;
  using Stage = PairStage;
  CDB_HD void operator()(uint32_t k, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const uint64_t bucket = buckets[k], c = cell[k];
    const uint32_t a = box[k];
    const vec4f alo = lo[a], ahi = hi[a];
    const GridParams p = *params;
    for (uint32_t t = k + 1; t < entries && buckets[t] == bucket; ++t) {
      if (cell[t] != c) continue;
      const uint32_t b = box[t];
      const vec4f blo = lo[b], bhi = hi[b];
      if (!overlaps(alo, ahi, blo, bhi)) continue;
      const uint64_t home = pack_cell(cell_coord(max_of(alo.x, blo.x), p.origin[0], p.inv_cell),
                                      cell_coord(max_of(alo.y, blo.y), p.origin[1], p.inv_cell),
                                      cell_coord(max_of(alo.z, blo.z), p.origin[2], p.inv_cell));
      if (home == c) out.emit(a, b);
    }
  }
#if defined(__CUDACC__)
  __device__ void flush(Stage& s) const { sink.flush(s); }
#endif
};

// One thread per box: against every large box. A pair of two large boxes is reported by
// the thread of the larger index only.
struct LargePairsFn {
  const vec4f* lo;
  const vec4f* hi;
  const uint32_t* counts;
  const uint32_t* large;
  const uint32_t* large_count;
  PairSink sink;
  using Stage = PairStage;
  CDB_HD void operator()(uint32_t j, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const uint32_t count = *large_count;
    const bool j_large = counts[j] == 0;
    const vec4f jlo = lo[j], jhi = hi[j];
    for (uint32_t q = 0; q < count; ++q) {
      const uint32_t a = large[q];
      if (a == j || (j_large && j < a)) continue;
      if (overlaps(jlo, jhi, lo[a], hi[a])) out.emit(a, j);
    }
  }
#if defined(__CUDACC__)
  __device__ void flush(Stage& s) const { sink.flush(s); }
#endif
};

// Workspace of the hash: per-box arrays sized from the triangle count, per-entry arrays
// from an estimate of entries per box; growth beyond either is logged and counted.
template <class Exec>
struct SpatialHash {
  static constexpr size_t kEntriesPerBoxEstimate = 8;

  explicit SpatialHash(Exec& exec) {
    MemoryResource& mr = exec.memory();
    lo.bind(mr, "hash.lo");
    hi.bind(mr, "hash.hi");
    counts.bind(mr, "hash.counts");
    offsets.bind(mr, "hash.offsets");
    large.bind(mr, "hash.large");
    large_count.bind(mr, "hash.large_count");
    stats.bind(mr, "hash.stats");
    params.bind(mr, "hash.params");
    totals.bind(mr, "hash.totals");
    keys.bind(mr, "hash.keys");
    sorted_keys.bind(mr, "hash.sorted_keys");
    entry_ids.bind(mr, "hash.entry_ids");
    sorted_ids.bind(mr, "hash.sorted_ids");
    entry_box.bind(mr, "hash.entry_box");
    sorted_box.bind(mr, "hash.sorted_box");
    entry_cell.bind(mr, "hash.entry_cell");
    sorted_cell.bind(mr, "hash.sorted_cell");
    temp.bind(mr, "hash.temp");
  }

  void reserve(Exec& exec, uint32_t n) {
    for (auto* a : {&lo, &hi}) a->reserve(n);
    for (auto* a : {&counts, &offsets, &large}) a->reserve(n);
    large_count.reserve(1);
    stats.reserve(1);
    params.reserve(1);
    totals.reserve(1);
    reserve_entries(exec, n, std::max<size_t>(1024, kEntriesPerBoxEstimate * n));
  }

  void reserve_entries(Exec& exec, uint32_t n, size_t entries) {
    for (auto* a : {&keys, &sorted_keys, &entry_cell, &sorted_cell}) a->reserve(entries);
    for (auto* a : {&entry_ids, &sorted_ids, &entry_box, &sorted_box}) a->reserve(entries);
    size_t t = exec.sort_temp_bytes(entries);
    t = std::max(t, exec.scan_temp_bytes(n));
    t = std::max(t, exec.template reduce_temp_bytes_of<GridStats>(n));
    t = std::max(t, exec.template reduce_temp_bytes_of<EntryTotals>(n));
    temp.reserve(t);
  }

  Array<vec4f> lo, hi;
  Array<uint32_t> counts, offsets, large, large_count;
  Array<GridStats> stats;
  Array<GridParams> params;
  Array<EntryTotals> totals;
  Array<uint64_t> keys, sorted_keys;
  Array<uint32_t> entry_ids, sorted_ids, entry_box, sorted_box;
  Array<uint64_t> entry_cell, sorted_cell;
  Array<std::byte> temp;
  // Set by hash_build for hash_pairs.
  uint32_t num_entries = 0, num_large = 0;
};

template <class Exec>
void hash_boxes(Exec& exec, SpatialHash<Exec>& h, const MeshView& mesh) {
  exec.for_each_n(mesh.num_faces, FaceBoxFn{mesh, h.lo.data(), h.hi.data()});
}

// Grid, registration, sort. Reads the entry totals back once per grid tried; returns how
// many times the cell size had to grow.
template <class Exec>
uint32_t hash_build(Exec& exec, SpatialHash<Exec>& h, uint32_t n) {
  h.num_entries = h.num_large = 0;
  if (n == 0) return 0;
  exec.reduce(n, GridStatsFn{h.lo.data(), h.hi.data()}, GridStatsOp{}, GridStatsOp::identity(),
              h.stats.data(), h.temp.data(), h.temp.size());
  uint32_t regrids = 0;
  double scale = 1.0;
  EntryTotals totals{};
  for (;;) {
    exec.for_each_n(1, GridParamsFn{h.stats.data(), n, scale, h.params.data()});
    exec.fill(h.large_count.data(), 1, 0u);
    exec.for_each_n(n, CountCellsFn{h.lo.data(), h.hi.data(), h.params.data(), h.counts.data(),
                                    h.large.data(), h.large_count.data()});
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
  if (entries > h.keys.capacity()) h.reserve_entries(exec, n, entries + entries / 4);
  exec.exclusive_scan(h.counts.data(), h.offsets.data(), n, h.temp.data(), h.temp.size());
  uint32_t bits = 1;
  while (bits < 32 && (uint64_t(1) << bits) < 2 * uint64_t(entries)) ++bits;
  exec.for_each_n(n, FillCellsFn{h.lo.data(), h.hi.data(), h.params.data(), h.counts.data(),
                                 h.offsets.data(), bits, h.keys.data(), h.entry_ids.data(),
                                 h.entry_box.data(), h.entry_cell.data()});
  exec.sort_pairs(h.keys.data(), h.sorted_keys.data(), h.entry_ids.data(), h.sorted_ids.data(),
                  entries, static_cast<int>(bits), h.temp.data(), h.temp.size());
  exec.for_each_n(entries, GatherEntriesFn{h.sorted_ids.data(), h.entry_box.data(),
                                           h.entry_cell.data(), h.sorted_box.data(),
                                           h.sorted_cell.data()});
  return regrids;
}

template <class Exec>
void hash_pairs(Exec& exec, const SpatialHash<Exec>& h, uint32_t n, const PairSink& sink) {
  exec.for_each_staged(h.num_entries,
                  PairsInCellsFn{h.num_entries, h.sorted_keys.data(), h.sorted_box.data(),
                                 h.sorted_cell.data(), h.lo.data(), h.hi.data(), h.params.data(),
                                 sink},
                  Balance::uneven);
  if (h.num_large > 0)
    exec.for_each_staged(n, LargePairsFn{h.lo.data(), h.hi.data(), h.counts.data(), h.large.data(),
                                    h.large_count.data(), sink});
}

}  // namespace cdb
