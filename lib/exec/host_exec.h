#pragma once
// Host executor: the same functors the CUDA executor runs, over OpenMP threads. It is the
// backend CI tests, so it implements every primitive for real (no shortcuts).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <new>
#include <type_traits>
#include <vector>

#include "cdbench/core/aabb.h"
#include "cdbench/core/phase.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/tiles.h"
#include "cdbench/exec/exec_options.h"
#include "cdbench/exec/frame_graph.h"
#include "cdbench/exec/memory.h"
#include "cdbench/exec/tuning.h"

namespace cdb {

class HostMemory final : public MemoryResource {
 public:
  bool is_device() const override { return false; }

 private:
  void* do_allocate(size_t bytes) override {
    return ::operator new(bytes ? bytes : 1, std::align_val_t(64));
  }
  void do_deallocate(void* p, size_t) override { ::operator delete(p, std::align_val_t(64)); }
};

class HostFrameGraph;

class HostExec {
 public:
  static constexpr bool is_device = false;
  using FrameGraph = HostFrameGraph;

  explicit HostExec(const ExecOptions& = {}) {}

  MemoryResource& memory() { return memory_; }
  const char* name() const { return "cpu"; }
  // The threads that run at once (OpenMP's).
  uint64_t resident_threads() const { return uint64_t(omp_get_max_threads()); }

  template <class F>
  void for_each_n(size_t n, const F& f, Balance balance = Balance::even, Occupancy = Occupancy::plain) const {
    const int64_t count = static_cast<int64_t>(n);
    if (balance == Balance::even) {
#pragma omp parallel for schedule(static)
      for (int64_t i = 0; i < count; ++i) f(static_cast<uint32_t>(i));
    } else {
#pragma omp parallel for schedule(dynamic, 64)
      for (int64_t i = 0; i < count; ++i) f(static_cast<uint32_t>(i));
    }
  }

  // Staged appends (see CudaExec): the host has no block stage, so f(i, nullptr) appends
  // directly.
  template <class F>
  void for_each_staged(size_t n, const F& f, Balance balance = Balance::even, Occupancy = Occupancy::plain) const {
    for_each_n(n, [&f](uint32_t i) { f(i, static_cast<typename F::Stage*>(nullptr)); }, balance);
  }

  // F's phases in one block (see CudaExec): on the host, one thread runs each phase.
  // The block's shared memory is kept from call to call (a refit runs this every frame, and a
  // frame allocates nothing once sizes settle), zeroed each time as a fresh one was.
  template <class F>
  void in_one_block(const F& f) const {
    using Shared = typename F::Shared;
    static_assert(std::is_trivially_copyable_v<Shared> && alignof(Shared) <= alignof(std::max_align_t),
                  "block memory is reused as plain bytes");
    const size_t words = (sizeof(Shared) + sizeof(std::max_align_t) - 1) / sizeof(std::max_align_t);
    if (block_shared_.size() < words) block_shared_.resize(words);
    std::memset(static_cast<void*>(block_shared_.data()), 0, sizeof(Shared));
    Shared* shared = new (block_shared_.data()) Shared;
    const uint32_t phases = f.phases();
    for (uint32_t p = 0; p < phases; ++p) f.phase(p, 0, 1, *shared);
  }

  // Tiles (exec/tiles.h) whose indices share one F::Shared (see CudaExec): each tile runs
  // its indices in order on one thread, after f.init for every lane.
  template <class F>
  void for_each_tile(const Tiles& tiles, const F& f) const {
    each_tile(tiles, f, [&f](uint32_t first, uint32_t last, typename F::Shared& shared) {
      for (uint32_t i = first; i <= last; ++i) f(i, first, last, shared);
    });
  }

  // Tiles in phases (see CudaExec): each tile runs phase 0 for every lane, then each later
  // phase for every lane, on one thread.
  template <class F>
  void for_each_tile_in_phases(const Tiles& tiles, const F& f) const {
    each_tile(tiles, f, [&f](uint32_t first, uint32_t last, typename F::Shared& shared) {
      for (uint32_t lane = 0; lane < F::kTile; ++lane) f.phase(0, lane, first, last, shared);
      const uint32_t phases = f.phases(shared);
      for (uint32_t p = 1; p < phases; ++p)
        for (uint32_t lane = 0; lane <= last - first; ++lane) f.phase(p, lane, first, last, shared);
    });
  }

  // Scan in two passes over kScanChunks chunks: the chunks' sums, then each chunk scanned
  // from the sum before it. The temporary storage holds the chunks' sums.
  size_t scan_temp_bytes(size_t) const { return kScanChunks * sizeof(uint32_t); }
  // out[i] = in[0] + ... + in[i - 1] (mod 2^32); in and out may be the same array.
  void exclusive_scan(const uint32_t* in, uint32_t* out, size_t n, void* temp, size_t temp_bytes) const;
  // Two scans, as CudaExec::exclusive_scan_pair; temp holds scan_temp_bytes of the longer.
  void exclusive_scan_pair(const uint32_t* in0, uint32_t* out0, size_t n0, const uint32_t* in1, uint32_t* out1,
                           size_t n1, void* temp, size_t temp_bytes) const {
    exclusive_scan(in0, out0, n0, temp, temp_bytes);
    exclusive_scan(in1, out1, n1, temp, temp_bytes);
  }

  // Radix sort in digits of kSortDigitBits over chunks of consecutive keys: each chunk
  // counts its digits, then scatters its keys in order behind the earlier chunks' keys of
  // the same digit, so the sort is stable however many threads run. The temporary storage
  // holds a digit count per chunk and a second buffer of keys and values.
  static constexpr size_t kSortBuckets = size_t(1) << kSortDigitBits;
  // At most kSortChunks, fewer below kSortChunkKeys keys each (never decreasing with n, so
  // storage sized for a capacity serves every smaller sort).
  static size_t sort_chunks(size_t n) {
    return std::clamp<size_t>((n + kSortChunkKeys - 1) / kSortChunkKeys, 1, kSortChunks);
  }
  size_t sort_temp_bytes(size_t n) const {
    return sort_chunks(n) * kSortBuckets * sizeof(size_t) + n * (sizeof(uint64_t) + sizeof(uint32_t));
  }
  // Stable LSD radix sort of (key, value) on key bits [0, end_bit): keys equal in those
  // bits keep their order, whatever their higher bits. Inputs and outputs must not overlap.
  void sort_pairs(const uint64_t* keys_in, uint64_t* keys_out, const uint32_t* values_in,
                  uint32_t* values_out, size_t n, int end_bit, void* temp,
                  size_t temp_bytes) const;
  // The same sort without values (CUB's SortKeys).
  size_t sort_keys_temp_bytes(size_t n) const {
    return sort_chunks(n) * kSortBuckets * sizeof(size_t) + n * sizeof(uint64_t);
  }
  void sort_keys(const uint64_t* keys_in, uint64_t* keys_out, size_t n, int end_bit, void* temp,
                 size_t temp_bytes) const;

  size_t reduce_temp_bytes(size_t) const { return 0; }
  template <class F>
  void reduce_box(size_t n, const F& box_of, Aabb<float>* out, void*, size_t) const {
    Aabb<float> total = Aabb<float>::empty();
#pragma omp parallel
    {
      Aabb<float> local = Aabb<float>::empty();
#pragma omp for schedule(static) nowait
      for (int64_t i = 0; i < static_cast<int64_t>(n); ++i) local.grow(box_of(uint32_t(i)));
#pragma omp critical
      total.grow(local);
    }
    *out = total;
  }

  // Generic reduction of map(i) under an associative, commutative op. A fixed number of
  // chunks combined in order, so the result does not depend on the thread count.
  template <class T>
  size_t reduce_temp_bytes_of(size_t) const {
    return kReduceChunks * sizeof(T);
  }
  template <class T, class F, class Op>
  void reduce(size_t n, const F& map, const Op& op, const T& identity, T* out, void* temp,
              size_t) const {
    T* partial = static_cast<T*>(temp);
    const int64_t chunks = static_cast<int64_t>(kReduceChunks);
#pragma omp parallel for schedule(static)
    for (int64_t c = 0; c < chunks; ++c) {
      T acc = identity;
      const size_t end = n * size_t(c + 1) / kReduceChunks;
      for (size_t i = n * size_t(c) / kReduceChunks; i < end; ++i)
        acc = op(acc, map(static_cast<uint32_t>(i)));
      partial[c] = acc;
    }
    T total = identity;
    for (int64_t c = 0; c < chunks; ++c) total = op(total, partial[c]);
    *out = total;
  }

  template <class T>
  void fill(T* p, size_t n, const T& v) const {
    for_each_n(n, [=](uint32_t i) { p[i] = v; });
  }
  template <class T>
  void copy_to_host(T* dst, const T* src, size_t n) const {
    ++host_syncs_;
    if (n) std::memcpy(dst, src, n * sizeof(T));
  }
  template <class T>
  void copy_from_host(T* dst, const T* src, size_t n) const {
    if (n) std::memcpy(dst, src, n * sizeof(T));
  }
  template <class T>
  void copy(T* dst, const T* src, size_t n) const {
    if (n) std::memcpy(dst, src, n * sizeof(T));
  }
  // A frame's input from the host (see CudaExec): a copy, no staging needed.
  void reserve_upload(size_t) {}
  template <class T>
  void upload(T* dst, const T* src, size_t n) {
    if (n) std::memcpy(dst, src, n * sizeof(T));
  }
  // A resident frame's positions are host memory the caller wrote before the frame: nothing
  // to wait for (see CudaExec).
  void wait_for_stream(void*) const {}
  // A side task (see CudaExec::on_side) runs here and now, its wall time kept for
  // finish_side, which counts a synchronization as the CUDA executor's does.
  void reserve_side() {}
  template <class F>
  void on_side(F&& work) {
    const auto begin = std::chrono::steady_clock::now();
    work();
    side_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
  }
  void mark_side_fork() const {}
  bool side_done() const { return true; }
  void drop_side() {}
  double finish_side() {
    ++host_syncs_;
    return side_ms_;
  }
  void sync() const { ++host_syncs_; }
  // Read-backs and waits so far: where the CUDA executor would stop the host until the
  // device caught up, counted the same way so CPU tests can check the per-frame count.
  uint64_t host_syncs() const { return host_syncs_; }

 private:
  // Each tile on one thread: its F::Shared initialized lane by lane, then run(first, last,
  // shared).
  template <class F, class Run>
  void each_tile(const Tiles& tiles, const F& f, const Run& run) const {
    const int64_t count = *tiles.count;
#pragma omp parallel for schedule(dynamic, 1)
    for (int64_t t = 0; t < count; ++t) {
      typename F::Shared shared;
      for (uint32_t lane = 0; lane < F::kTile; ++lane) f.init(shared, lane);
      run(tiles.first[t], tiles.first[t + 1] - 1, shared);
    }
  }

  HostMemory memory_;
  mutable std::vector<std::max_align_t> block_shared_;  // in_one_block's
  mutable uint64_t host_syncs_ = 0;
  double side_ms_ = 0.0;  // the last side task's wall time
};

// Wall-clock phase timer for the host executor; with phases off only the frame and its
// upload, as CudaPhaseTimer.
class HostPhaseTimer {
 public:
  explicit HostPhaseTimer(HostExec& exec, bool phases = true) : exec_(&exec), phases_(phases) {}
  void start(Phase p) {
    if (timed(p)) begin_[size_t(p)] = clock::now();
  }
  void stop(Phase p) {
    if (!timed(p)) return;
    ms_[size_t(p)] +=
        std::chrono::duration<double, std::milli>(clock::now() - begin_[size_t(p)]).count();
  }
  void start_frame() {
    ms_.fill(0.0);
    syncs_at_start_ = exec_->host_syncs();
    frame_begin_ = clock::now();
  }
  void stop_frame() {
    frame_ms_ = std::chrono::duration<double, std::milli>(clock::now() - frame_begin_).count();
  }
  // As CudaPhaseTimer::force_phases.
  void force_phases(bool on) { forced_ = on; }
  // Valid once the executor has synchronized after stop_frame().
  double phase_ms(Phase p) const { return ms_[size_t(p)]; }
  double frame_ms() const { return frame_ms_; }
  // Synchronization points since start_frame(), the frame's read-back included.
  uint64_t frame_syncs() const { return exec_->host_syncs() - syncs_at_start_; }

 private:
  bool timed(Phase p) const { return phases_ || forced_ || p == Phase::upload; }
  const HostExec* exec_;
  bool phases_;
  bool forced_ = false;
  uint64_t syncs_at_start_ = 0;
  using clock = std::chrono::steady_clock;
  std::array<clock::time_point, kPhaseCount> begin_{};
  std::array<double, kPhaseCount> ms_{};
  clock::time_point frame_begin_{};
  double frame_ms_ = 0.0;
};

// No graphs on the host: the recorded work runs as it comes, every frame.
class HostFrameGraph {
 public:
  template <class F>
  FrameGraphRun run(HostExec&, HostPhaseTimer&, const FrameGraphKey&, F&& launch) {
    launch();
    return FrameGraphRun::plain;
  }
  void invalidate() {}
};

}  // namespace cdb
