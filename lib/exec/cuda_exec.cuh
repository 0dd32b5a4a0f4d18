#pragma once
// CUDA executor: runs the functors of lib/ as kernels on one stream; scans and sorts go
// through CUB with temporary storage the caller provides (queried first, CUB style).
// Included only by .cu files; host code reaches the CUDA backend through
// make_cuda_pipeline (registry/pipeline_kinds.h, defined in registry/cuda_backend.cu).
#include <cuda_runtime.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cub/block/block_reduce.cuh>
#include <vector>

#include "cdbench/core/aabb.h"
#include "cdbench/core/append_stage.h"
#include "cdbench/core/phase.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/tiles.h"
#include "cdbench/exec/exec_options.h"
#include "cdbench/exec/frame_graph.h"
#include "cdbench/exec/tuning.h"
#include "cdbench/exec/memory.h"

namespace cdb {

void cuda_check(cudaError_t status, const char* what);

class CudaMemory final : public MemoryResource {
 public:
  bool is_device() const override { return true; }

 private:
  void* do_allocate(size_t bytes) override;
  void do_deallocate(void* p, size_t bytes) override;
};

// The first thing every kernel of the executor does (ExecOptions::dependent_launch): let the
// next kernel on the stream be scheduled now, its blocks waiting as this one's do, then wait
// until the kernel before this one has completed and its writes are visible. Nothing runs
// before the wait, so the order is that of serial launches; launched without the attribute
// both instructions return at once.
__device__ __forceinline__ void dependent_launch_entry() {
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ >= 900
  asm volatile("griddepcontrol.launch_dependents;" ::: "memory");
  asm volatile("griddepcontrol.wait;" ::: "memory");
#endif
}

// A functor whose indices share work within a warp (front/warp_traversal.h) runs on every
// thread of the launch, those past n included, as f.warp(i, n, stage): all lanes of a warp
// take part in its warp-wide votes and shuffles.
template <class F>
concept WarpCooperative = requires(const F& f, typename F::Stage* stage) { f.warp(0u, 0u, stage); };

template <class F>
__device__ __forceinline__ void for_each_body(uint32_t n, const F& f) {
  dependent_launch_entry();
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if constexpr (WarpCooperative<F>)
    f.warp(i, n, static_cast<typename F::Stage*>(nullptr));
  else if (i < n)
    f(i);
}

template <class F>
__global__ void for_each_kernel(uint32_t n, F f) {
  for_each_body(n, f);
}

// The same for a functor that asks for min_blocks_per_sm<F>() resident blocks (exec/tuning.h).
template <class F>
__global__ void __launch_bounds__(kForEachThreads, min_blocks_per_sm<F>()) for_each_bounded_kernel(uint32_t n, F f) {
  for_each_body(n, f);
}

// Tiles of at most F::kTile consecutive indices (exec/tiles.h), taken in turn by the blocks;
// a tile's threads share one F::Shared in shared memory, initialized lane by lane before any
// index runs.
// The block's tiles in turn: `shared` initialized lane by lane, then run(first, last).
template <class F, class Run>
__device__ __forceinline__ void for_each_block_tile(const Tiles& tiles, const F& f, typename F::Shared& shared,
                                                    const Run& run) {
  const uint32_t count = *tiles.count;
  for (uint32_t t = blockIdx.x; t < count; t += gridDim.x) {
    if (t != blockIdx.x) __syncthreads();  // the block's previous tile is done with `shared`
    f.init(shared, threadIdx.x);
    __syncthreads();
    run(tiles.first[t], tiles.first[t + 1] - 1);
  }
}

template <class F>
__global__ void __launch_bounds__(F::kTile) for_each_tile_kernel(Tiles tiles, F f) {
  dependent_launch_entry();
  __shared__ typename F::Shared shared;
  for_each_block_tile(tiles, f, shared, [&](uint32_t first, uint32_t last) {
    const uint32_t i = first + threadIdx.x;
    if (i <= last) f(i, first, last, shared);
  });
}

// The same tiles in phases: every thread of the block runs f.phase(p, lane, first, last)
// for phase 0, then for phases 1 .. f.phases(shared) - 1 (read from shared memory after
// phase 0), one block barrier after each.
template <class F>
__global__ void __launch_bounds__(F::kTile) for_each_tile_in_phases_kernel(Tiles tiles, F f) {
  dependent_launch_entry();
  __shared__ typename F::Shared shared;
  for_each_block_tile(tiles, f, shared, [&](uint32_t first, uint32_t last) {
    f.phase(0, threadIdx.x, first, last, shared);
    __syncthreads();
    const uint32_t phases = f.phases(shared);
    for (uint32_t p = 1; p < phases; ++p) {
      f.phase(p, threadIdx.x, first, last, shared);
      __syncthreads();
    }
  });
}

// One thread per index; the block shares one F::Stage (core/append_stage.h) that its indices
// append to and that F::flush writes out once every index of the block is done.
template <class F>
__device__ __forceinline__ void for_each_staged_body(uint32_t n, const F& f) {
  dependent_launch_entry();
  __shared__ typename F::Stage stage;
  if (threadIdx.x == 0) stage.reset();
  __syncthreads();
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if constexpr (WarpCooperative<F>)
    f.warp(i, n, &stage);
  else if (i < n)
    f(i, &stage);
  __syncthreads();
  f.flush(stage);
}

template <class F>
__global__ void for_each_staged_kernel(uint32_t n, F f) {
  for_each_staged_body(n, f);
}

template <class F>
__global__ void __launch_bounds__(kStagedThreads, min_blocks_per_sm<F>())
    for_each_staged_bounded_kernel(uint32_t n, F f) {
  for_each_staged_body(n, f);
}

// One block of kOneBlockThreads threads (exec/tuning.h) running F's phases (f.phases(), read from device
// memory by every thread alike) with a block barrier between them, sharing one F::Shared in
// dynamic shared memory.

template <class F>
__global__ void __launch_bounds__(kOneBlockThreads) in_one_block_kernel(F f) {
  dependent_launch_entry();
  extern __shared__ __align__(16) unsigned char shared_bytes[];
  auto& shared = *reinterpret_cast<typename F::Shared*>(shared_bytes);
  const uint32_t phases = f.phases();
  for (uint32_t p = 0; p < phases; ++p) {
    if (p > 0) __syncthreads();
    f.phase(p, threadIdx.x, blockDim.x, shared);
  }
}

struct BoxUnion {
  __device__ Aabb<float> operator()(const Aabb<float>& a, const Aabb<float>& b) const {
    Aabb<float> r = a;
    r.grow(b);
    return r;
  }
};

// The one reduction (CudaExec::reduce, and reduce_box through it): per-block partials, then
// one block combines them; both in a fixed order, so results are reproducible run to run.
template <class T, class F, class Op>
__global__ void __launch_bounds__(kReduceThreads)
    reduce_partials_kernel(uint32_t n, F map, Op op, T identity, T* partials) {
  dependent_launch_entry();
  using Reduce = cub::BlockReduce<T, kReduceThreads>;
  __shared__ typename Reduce::TempStorage storage;
  T acc = identity;
  for (uint32_t i = blockIdx.x * kReduceThreads + threadIdx.x; i < n;
       i += gridDim.x * kReduceThreads)
    acc = op(acc, map(i));
  const T block = Reduce(storage).Reduce(acc, op);
  if (threadIdx.x == 0) partials[blockIdx.x] = block;
}

template <class T, class Op>
__global__ void __launch_bounds__(kReduceThreads)
    reduce_final_kernel(const T* partials, uint32_t count, Op op, T identity, T* out) {
  dependent_launch_entry();
  using Reduce = cub::BlockReduce<T, kReduceThreads>;
  __shared__ typename Reduce::TempStorage storage;
  T acc = identity;
  for (uint32_t i = threadIdx.x; i < count; i += kReduceThreads) acc = op(acc, partials[i]);
  const T total = Reduce(storage).Reduce(acc, op);
  if (threadIdx.x == 0) *out = total;
}

// Every kernel of the executor is launched here: one place decides the launch attributes.
template <class... Params, class... Args>
void launch_kernel(cudaStream_t stream, bool dependent_launch, void (*kernel)(Params...), uint32_t blocks,
                   uint32_t threads, size_t shared_bytes, const Args&... args) {
  cudaLaunchAttribute dependent{};
  dependent.id = cudaLaunchAttributeProgrammaticStreamSerialization;
  dependent.val.programmaticStreamSerializationAllowed = 1;
  cudaLaunchConfig_t config{};
  config.gridDim = dim3(blocks);
  config.blockDim = dim3(threads);
  config.dynamicSmemBytes = shared_bytes;
  config.stream = stream;
  config.attrs = &dependent;
  config.numAttrs = dependent_launch ? 1 : 0;
  cuda_check(cudaLaunchKernelEx(&config, kernel, args...), "kernel launch");
}

template <class T>
struct FillFn {
  T* p;
  T v;
  __device__ void operator()(uint32_t i) const { p[i] = v; }
};

class CudaFrameGraph;

class CudaExec {
 public:
  static constexpr bool is_device = true;
  using FrameGraph = CudaFrameGraph;

  explicit CudaExec(const ExecOptions& options = {});
  ~CudaExec();
  CudaExec(const CudaExec&) = delete;
  CudaExec& operator=(const CudaExec&) = delete;

  MemoryResource& memory() { return memory_; }
  cudaStream_t stream() const { return stream_; }
  // Threads the GPU holds at once (SMs x threads per SM): a launch's wave.
  uint64_t resident_threads() const { return resident_threads_; }
  const char* name() const { return "cuda"; }

  // Occupancy::bounded: under F's __launch_bounds__, where F asks for some (exec/tuning.h).
  template <class F>
  void for_each_n(size_t n, const F& f, Balance = Balance::even, Occupancy occupancy = Occupancy::plain) const {
    launch_per_index<PlainIndexKernels>(n, f, occupancy);
  }

  // F's phases in one block (see in_one_block_kernel): work too small and too serial for the
  // whole GPU, whose hand-overs need only block-scope atomics and shared memory.
  template <class F>
  void in_one_block(const F& f) const {
    constexpr size_t bytes = sizeof(typename F::Shared);
    cuda_check(cudaFuncSetAttribute(in_one_block_kernel<F>, cudaFuncAttributeMaxDynamicSharedMemorySize, int(bytes)),
               "shared memory size");
    launch(in_one_block_kernel<F>, 1, kOneBlockThreads, bytes, f);
  }

  // Indices whose appends (pairs, front nodes) are staged per block in shared memory and
  // written out at the block's end (core/append_stage.h): f(i, stage), then f.flush(stage).
  template <class F>
  void for_each_staged(size_t n, const F& f, Balance = Balance::even, Occupancy occupancy = Occupancy::plain) const {
    launch_per_index<StagedIndexKernels>(n, f, occupancy);
  }

  // Indices in tiles (exec/tiles.h) whose indices share an F::Shared: threads of one block
  // here, so hand-overs inside a tile need only block-scope atomics (refit.h).
  template <class F>
  void for_each_tile(const Tiles& tiles, const F& f) const {
    if (tiles.blocks == 0) return;
    launch(for_each_tile_kernel<F>, tiles.blocks, F::kTile, 0, tiles, f);
  }

  // Tiles in phases with a block barrier between them (for_each_tile_in_phases_kernel).
  template <class F>
  void for_each_tile_in_phases(const Tiles& tiles, const F& f) const {
    if (tiles.blocks == 0) return;
    launch(for_each_tile_in_phases_kernel<F>, tiles.blocks, F::kTile, 0, tiles, f);
  }

  size_t scan_temp_bytes(size_t n) const;
  // Two exclusive scans at once (the count logs of a front's two kinds): while both have at
  // most kPairScanBlockMax values (exec/tuning.h), one launch with one block per array; past
  // it, one device scan each, two launches however short the array. temp holds
  // scan_temp_bytes of the longer.
  void exclusive_scan_pair(const uint32_t* in0, uint32_t* out0, size_t n0, const uint32_t* in1, uint32_t* out1,
                           size_t n1, void* temp, size_t temp_bytes) const;
  void exclusive_scan(const uint32_t* in, uint32_t* out, size_t n, void* temp,
                      size_t temp_bytes) const;

  size_t sort_temp_bytes(size_t n) const;
  void sort_pairs(const uint64_t* keys_in, uint64_t* keys_out, const uint32_t* values_in,
                  uint32_t* values_out, size_t n, int end_bit, void* temp,
                  size_t temp_bytes) const;

  size_t reduce_temp_bytes(size_t n) const { return reduce_temp_bytes_of<Aabb<float>>(n); }
  template <class F>
  void reduce_box(size_t n, const F& box_of, Aabb<float>* out, void* temp, size_t bytes) const {
    reduce(n, box_of, BoxUnion{}, Aabb<float>::empty(), out, temp, bytes);
  }

  // Generic reduction of map(i) under an associative, commutative op.
  template <class T>
  size_t reduce_temp_bytes_of(size_t) const {
    return kReduceBlocks * sizeof(T);
  }
  template <class T, class F, class Op>
  void reduce(size_t n, const F& map, const Op& op, const T& identity, T* out, void* temp,
              size_t) const {
    auto* partials = static_cast<T*>(temp);
    const uint32_t blocks = static_cast<uint32_t>(
        n == 0 ? 1 : std::min<size_t>(kReduceBlocks, (n + kReduceThreads - 1) / kReduceThreads));
    launch(reduce_partials_kernel<T, F, Op>, blocks, kReduceThreads, 0, uint32_t(n), map, op, identity,
           partials);
    launch(reduce_final_kernel<T, Op>, 1, kReduceThreads, 0, partials, blocks, op, identity, out);
  }

  template <class T>
  void fill(T* p, size_t n, const T& v) const {
    for_each_n(n, FillFn<T>{p, v});
  }
  template <class T>
  void copy_to_host(T* dst, const T* src, size_t n) const {
    copy_to_host_bytes(dst, src, n * sizeof(T));
  }
  template <class T>
  void copy_from_host(T* dst, const T* src, size_t n) const {
    copy_from_host_bytes(dst, src, n * sizeof(T));
  }
  template <class T>
  void copy(T* dst, const T* src, size_t n) const {
    copy_bytes(dst, src, n * sizeof(T));
  }
  // A frame's input from the host (its vertices) goes through a pinned staging buffer the
  // executor owns: one host copy into it, then an asynchronous DMA. From pageable memory the
  // driver stages the data itself and the stream waits on that, which was slower
  // (docs/design.md "Constants and their measurements"). reserve_upload sizes the buffer outside the
  // frame; a larger upload grows it (counted as a growth).
  void reserve_upload(size_t bytes);
  template <class T>
  void upload(T* dst, const T* src, size_t n) {
    upload_bytes(dst, src, n * sizeof(T));
  }
  // The work queued so far on `stream` (a cudaStream_t; nullptr: the legacy default stream)
  // comes before this executor's next launches: an event the executor's stream waits on,
  // no host synchronization. How a resident frame's positions, written by the caller on its
  // own stream, reach the frame (pipeline/device_mesh.h).
  void wait_for_stream(void* stream);
  // Work off the frames' critical path (--rebuild-ahead, pipeline/front_pipeline.h): every
  // launch `work` makes goes to a second stream, after all work queued so far on the
  // executor's stream, while the frames go on on that one. The executor's stream has the
  // device's highest priority and the side stream its lowest, so the block scheduler gives
  // the side's kernels only what the frames leave idle. No host synchronization: side_done()
  // asks whether the side's work has finished, finish_side() waits for it (a counted
  // synchronization) and gives the milliseconds it ran. reserve_side() creates the stream,
  // outside any frame; one side task at a time.
  void reserve_side();
  template <class F>
  void on_side(F&& work) {
    begin_side();
    try {
      work();
    } catch (...) {
      end_side();
      throw;
    }
    end_side();
  }
  // Marks the point on the executor's stream after which the next side task starts: work
  // queued after the mark and before on_side() runs beside the side task, not before it.
  // A frame marks the fork where the side's input is ready and queues its own kernels
  // first, so the side's host launches overlap the frame's device work (front_pipeline.h).
  void mark_side_fork();
  bool side_done() const;
  double finish_side();
  // Waits for a side task that will not be adopted (a run that ended with it in flight) and
  // forgets it; nothing if none runs.
  void drop_side();
  // Waits for the stream; every read-back ends in one. Counted: the frame loop reports the
  // synchronizations each frame made (target: one, the counters' read-back).
  void sync() const;
  uint64_t host_syncs() const { return host_syncs_; }

 private:
  template <class... Params, class... Args>
  void launch(void (*kernel)(Params...), uint32_t blocks, uint32_t threads, size_t shared_bytes,
              const Args&... args) const {
    launch_kernel(stream_, options_.dependent_launch, kernel, blocks, threads, shared_bytes, args...);
  }

  // The kernels of for_each_n and for_each_staged, one thread per index: their block size,
  // the plain kernel and the one under F's __launch_bounds__. Named through templates so
  // that a bounded kernel is instantiated only for a functor that asks for a bound.
  struct PlainIndexKernels {
    static constexpr uint32_t threads = kForEachThreads;
    template <class F>
    static auto plain() { return for_each_kernel<F>; }
    template <class F>
    static auto bounded() { return for_each_bounded_kernel<F>; }
  };
  struct StagedIndexKernels {
    static constexpr uint32_t threads = kStagedThreads;
    template <class F>
    static auto plain() { return for_each_staged_kernel<F>; }
    template <class F>
    static auto bounded() { return for_each_staged_bounded_kernel<F>; }
  };

  // One thread per index of n, in blocks of Kernels::threads: the bounded kernel where
  // `occupancy` asks for it and F has a bound (exec/tuning.h), else the plain one.
  template <class Kernels, class F>
  void launch_per_index(size_t n, const F& f, Occupancy occupancy) const {
    if (n == 0) return;
    constexpr uint32_t threads = Kernels::threads;
    const uint32_t blocks = static_cast<uint32_t>((n + threads - 1) / threads);
    if constexpr (min_blocks_per_sm<F>() > 0)
      if (occupancy == Occupancy::bounded) {
        launch(Kernels::template bounded<F>(), blocks, threads, 0, static_cast<uint32_t>(n), f);
        return;
      }
    launch(Kernels::template plain<F>(), blocks, threads, 0, static_cast<uint32_t>(n), f);
  }
  void copy_to_host_bytes(void* dst, const void* src, size_t bytes) const;
  void copy_from_host_bytes(void* dst, const void* src, size_t bytes) const;
  void copy_bytes(void* dst, const void* src, size_t bytes) const;
  void upload_bytes(void* dst, const void* src, size_t bytes);
  void begin_side();
  void end_side();
  ExecOptions options_;
  uint64_t resident_threads_ = 0;
  cudaStream_t stream_ = nullptr;
  CudaMemory memory_;
  mutable uint64_t host_syncs_ = 0;
  void* staging_ = nullptr;  // pinned host memory of upload()
  size_t staging_bytes_ = 0;
  cudaEvent_t staging_copied_ = nullptr;  // recorded after the last upload's copy
  cudaEvent_t input_ready_ = nullptr;     // wait_for_stream's, recorded on the caller's stream
  cudaStream_t side_stream_ = nullptr;    // on_side's (reserve_side)
  cudaEvent_t side_fork_ = nullptr;       // the executor's stream's work before the side task
  cudaEvent_t side_begin_ = nullptr, side_end_ = nullptr;  // the side task's span
  bool side_pending_ = false;             // a side task was queued and not finished
  bool side_fork_marked_ = false;         // mark_side_fork() recorded side_fork_ for the next task
};

// Phase timer from CUDA events on the executor's stream; a phase that runs several times
// in a frame (a query re-run after its pair buffer grew) adds up. With phases off
// (--phase-timing off) only the frame and its upload are timed: no event between kernels,
// which in a recorded frame are graph nodes of their own and keep the kernels around them
// from launching early (ExecOptions::dependent_launch).
class CudaPhaseTimer {
 public:
  explicit CudaPhaseTimer(CudaExec& exec, bool phases = true);
  ~CudaPhaseTimer();
  CudaPhaseTimer(const CudaPhaseTimer&) = delete;
  CudaPhaseTimer& operator=(const CudaPhaseTimer&) = delete;
  void start(Phase p);
  void stop(Phase p);
  void start_frame();
  void stop_frame();
  // Times every phase from here until force_phases(false), phases off or not: the build
  // frame's generate, which prices a maintenance generate (pipeline/front_maintenance.h).
  void force_phases(bool on) { forced_ = on; }
  double phase_ms(Phase p) const;
  double frame_ms() const;
  // Synchronizations of the executor since start_frame(), the frame's read-back included.
  uint64_t frame_syncs() const { return exec_->host_syncs() - syncs_at_start_; }

  struct Span {
    Phase phase;
    cudaEvent_t begin, end;
  };
  // The phases a CUDA graph times: while its work is captured, start/stop record their
  // events as event nodes of the graph; a replay of the graph records the same events again,
  // so the frame takes over the spans (and the pool slots) of the capture.
  struct Recording {
    size_t first_event = 0, end_event = 0;
    std::vector<Span> spans;
  };
  void begin_recording();
  Recording end_recording();
  // False when this frame's events so far differ from the capture's (the pool slots the
  // graph records would clash): the caller captures again.
  bool replay(const Recording& r);

 private:
  cudaEvent_t next_event();
  void record(cudaEvent_t e);
  bool timed(Phase p) const { return phases_ || forced_ || p == Phase::upload; }
  const CudaExec* exec_;
  bool phases_;
  bool forced_ = false;
  uint64_t syncs_at_start_ = 0;
  cudaStream_t stream_;
  std::vector<cudaEvent_t> pool_;
  size_t used_ = 0;
  std::vector<Span> spans_;
  std::array<cudaEvent_t, kPhaseCount> open_{};
  cudaEvent_t frame_begin_ = nullptr, frame_end_ = nullptr;
  bool recording_ = false;
  size_t recording_first_event_ = 0, recording_first_span_ = 0;
};

// Recorded frames (CUDA graphs). run() captures the work `launch` enqueues on the
// executor's stream into a graph the first time a key is seen, then launches it; with a key
// seen before it only launches that graph: one launch instead of one per kernel, without
// the gaps between them. Two recordings are kept (swept boxes alternate two vertex buffers,
// so steady frames alternate two keys); a new key takes the older slot, updating its
// instantiated graph in place (cudaGraphExecUpdate) when the shape allows.
class CudaFrameGraph {
 public:
  CudaFrameGraph() = default;
  ~CudaFrameGraph();
  CudaFrameGraph(const CudaFrameGraph&) = delete;
  CudaFrameGraph& operator=(const CudaFrameGraph&) = delete;

  template <class F>
  FrameGraphRun run(CudaExec& exec, CudaPhaseTimer& timer, const FrameGraphKey& key, F&& launch) {
    ++clock_;
    for (Slot& s : slots_) {
      if (s.valid && s.key == key && timer.replay(s.recording)) {
        s.last_used = clock_;
        launch_graph(exec, s);
        ++replays_;
        return FrameGraphRun::replayed;
      }
    }
    Slot& s = *std::min_element(slots_.begin(), slots_.end(),
                                [](const Slot& a, const Slot& b) { return a.last_used < b.last_used; });
    begin_capture(exec, timer, s);
    try {
      launch();
    } catch (...) {
      abandon_capture(exec, timer);
      throw;
    }
    end_capture(exec, timer, s);
    s.key = key;
    s.valid = true;
    s.last_used = clock_;
    launch_graph(exec, s);
    ++captures_;
    return FrameGraphRun::captured;
  }
  // The next run() captures again whatever its key.
  void invalidate() {
    for (Slot& s : slots_) s.valid = false;
  }
  uint64_t captures() const { return captures_; }
  uint64_t replays() const { return replays_; }

 private:
  struct Slot {
    cudaGraphExec_t graph_exec = nullptr;
    bool valid = false;
    FrameGraphKey key{};
    CudaPhaseTimer::Recording recording;
    uint64_t last_used = 0;
  };
  void begin_capture(CudaExec& exec, CudaPhaseTimer& timer, Slot& s);
  void end_capture(CudaExec& exec, CudaPhaseTimer& timer, Slot& s);
  void abandon_capture(CudaExec& exec, CudaPhaseTimer& timer);
  void launch_graph(CudaExec& exec, const Slot& s);
  // Recordings kept at once, least recently used replaced: swept boxes alternate two vertex
  // buffers.
  std::array<Slot, 2> slots_;
  uint64_t clock_ = 0, captures_ = 0, replays_ = 0;
};

}  // namespace cdb
