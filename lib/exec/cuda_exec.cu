#include <cub/block/block_scan.cuh>
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>
#include <cstring>
#include <string>

#include "cdbench/core/error.h"
#include "cdbench/exec/cuda_exec.cuh"

namespace cdb {

void cuda_check(cudaError_t status, const char* what) {
  if (status != cudaSuccess)
    fail(std::string("CUDA error in ") + what + ": " + cudaGetErrorString(status));
}

void* CudaMemory::do_allocate(size_t bytes) {
  void* p = nullptr;
  const cudaError_t status = cudaMalloc(&p, bytes ? bytes : 1);
  if (status != cudaSuccess) {
    size_t free_b = 0, total_b = 0;
    cudaMemGetInfo(&free_b, &total_b);
    fail("out of device memory: asked for " + std::to_string(bytes) + " bytes with " +
         std::to_string(free_b) + " of " + std::to_string(total_b) + " free (" +
         cudaGetErrorString(status) + ")");
  }
  return p;
}

void CudaMemory::do_deallocate(void* p, size_t) { cudaFree(p); }

namespace {

// Compiled like every kernel of this build; its attributes say which of the build's code
// variants the driver loaded for this GPU.
__global__ void code_variant_kernel() {}

// The virtual architecture (PTX version x 10, e.g. 90) the loaded kernels were compiled
// from: below 90 they lack the griddepcontrol wait (dependent_launch_entry).
int loaded_ptx_version() {
  cudaFuncAttributes attributes{};
  cuda_check(cudaFuncGetAttributes(&attributes, code_variant_kernel), "kernel attribute query");
  return attributes.ptxVersion;
}

}  // namespace

CudaExec::CudaExec(const ExecOptions& options) : options_(options) {
  // A build without a visible GPU embeds compute_75 PTX (cmake/cuda_architectures.cmake),
  // which a Hopper card may be handed when it has no sm_90 code: launched with programmatic
  // serialization, kernels without the wait would overlap their predecessors.
  if (loaded_ptx_version() < 90) options_.dependent_launch = false;
  int device = 0, sms = 0, per_sm = 0;
  cuda_check(cudaGetDevice(&device), "device query");
  cuda_check(cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, device), "SM count query");
  cuda_check(cudaDeviceGetAttribute(&per_sm, cudaDevAttrMaxThreadsPerMultiProcessor, device), "threads per SM query");
  resident_threads_ = uint64_t(sms) * uint64_t(per_sm);
  // The highest priority: a side task (on_side) gets only what the frames leave idle.
  int least = 0, greatest = 0;
  cuda_check(cudaDeviceGetStreamPriorityRange(&least, &greatest), "stream priority query");
  cuda_check(cudaStreamCreateWithPriority(&stream_, cudaStreamNonBlocking, greatest), "stream creation");
  cuda_check(cudaEventCreateWithFlags(&staging_copied_, cudaEventDisableTiming), "event creation");
  cuda_check(cudaEventCreateWithFlags(&input_ready_, cudaEventDisableTiming), "event creation");
}

CudaExec::~CudaExec() {
  if (staging_) cudaFreeHost(staging_);
  if (staging_copied_) cudaEventDestroy(staging_copied_);
  if (input_ready_) cudaEventDestroy(input_ready_);
  if (side_stream_) {
    cudaStreamSynchronize(side_stream_);
    cudaStreamDestroy(side_stream_);
    for (cudaEvent_t e : {side_fork_, side_begin_, side_end_}) cudaEventDestroy(e);
  }
  if (stream_) cudaStreamDestroy(stream_);
}

void CudaExec::reserve_side() {
  if (side_stream_) return;
  int least = 0, greatest = 0;
  cuda_check(cudaDeviceGetStreamPriorityRange(&least, &greatest), "stream priority query");
  cuda_check(cudaStreamCreateWithPriority(&side_stream_, cudaStreamNonBlocking, least), "side stream creation");
  cuda_check(cudaEventCreateWithFlags(&side_fork_, cudaEventDisableTiming), "event creation");
  cuda_check(cudaEventCreate(&side_begin_), "event creation");
  cuda_check(cudaEventCreate(&side_end_), "event creation");
}

void CudaExec::begin_side() {
  if (!side_stream_) fail("a side task before reserve_side");
  if (side_pending_) fail("a side task while another runs");
  if (!side_fork_marked_) cuda_check(cudaEventRecord(side_fork_, stream_), "event record");
  side_fork_marked_ = false;
  cuda_check(cudaStreamWaitEvent(side_stream_, side_fork_, 0), "side stream wait");
  cuda_check(cudaEventRecord(side_begin_, side_stream_), "event record");
  std::swap(stream_, side_stream_);
}

void CudaExec::end_side() {
  std::swap(stream_, side_stream_);
  cuda_check(cudaEventRecord(side_end_, side_stream_), "event record");
  side_pending_ = true;
}

void CudaExec::mark_side_fork() {
  if (!side_stream_) fail("a side fork before reserve_side");
  cuda_check(cudaEventRecord(side_fork_, stream_), "event record");
  side_fork_marked_ = true;
}

bool CudaExec::side_done() const {
  if (!side_pending_) return true;
  const cudaError_t status = cudaEventQuery(side_end_);
  if (status == cudaErrorNotReady) return false;
  cuda_check(status, "side task");
  return true;
}

double CudaExec::finish_side() {
  if (!side_pending_) return 0.0;
  cuda_check(cudaEventSynchronize(side_end_), "side task");
  ++host_syncs_;
  side_pending_ = false;
  float ms = 0.0f;
  cuda_check(cudaEventElapsedTime(&ms, side_begin_, side_end_), "side task time");
  return double(ms);
}

void CudaExec::drop_side() {
  if (side_pending_) finish_side();
}

void CudaExec::reserve_upload(size_t bytes) {
  if (bytes <= staging_bytes_) return;
  // The buffer being replaced may still feed a copy.
  cuda_check(cudaEventSynchronize(staging_copied_), "upload staging");
  if (staging_) cudaFreeHost(staging_);
  staging_ = nullptr;
  cuda_check(cudaMallocHost(&staging_, bytes), "upload staging allocation");
  if (staging_bytes_ > 0) memory_.note_growth("upload_staging (bytes)", staging_bytes_, bytes);
  staging_bytes_ = bytes;
}

void CudaExec::wait_for_stream(void* stream) {
  cuda_check(cudaEventRecord(input_ready_, static_cast<cudaStream_t>(stream)), "event record on the caller's stream");
  cuda_check(cudaStreamWaitEvent(stream_, input_ready_, 0), "wait for the caller's stream");
}

void CudaExec::upload_bytes(void* dst, const void* src, size_t bytes) {
  if (!bytes) return;
  reserve_upload(bytes);
  // The last upload's copy must have left the staging buffer before it is overwritten. Every
  // frame ends in a read-back, so by the next frame's upload this never waits.
  cuda_check(cudaEventSynchronize(staging_copied_), "upload staging");
  std::memcpy(staging_, src, bytes);
  cuda_check(cudaMemcpyAsync(dst, staging_, bytes, cudaMemcpyHostToDevice, stream_), "upload");
  cuda_check(cudaEventRecord(staging_copied_, stream_), "event record");
}

size_t CudaExec::scan_temp_bytes(size_t n) const {
  size_t bytes = 0;
  cuda_check(cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<const uint32_t*>(nullptr),
                                           static_cast<uint32_t*>(nullptr), int64_t(n), stream_),
             "scan size query");
  return bytes;
}

void CudaExec::exclusive_scan(const uint32_t* in, uint32_t* out, size_t n, void* temp,
                              size_t temp_bytes) const {
  if (n == 0) return;
  cuda_check(cub::DeviceScan::ExclusiveSum(temp, temp_bytes, in, out, int64_t(n), stream_),
             "exclusive scan");
}

namespace {

struct ScanJob {
  const uint32_t* in;
  uint32_t* out;
  uint32_t n;
};

// Block b scans job b alone, tile after tile of kPairScanThreads * kPairScanItems values,
// each thread a run of kPairScanItems consecutive ones, carrying the running total.
__global__ void __launch_bounds__(kPairScanThreads) pair_scan_kernel(ScanJob first, ScanJob second) {
  dependent_launch_entry();
  const ScanJob job = blockIdx.x == 0 ? first : second;
  using Scan = cub::BlockScan<uint32_t, kPairScanThreads>;
  __shared__ typename Scan::TempStorage storage;
  uint32_t carry = 0;
  for (uint32_t base = 0; base < job.n; base += kPairScanThreads * kPairScanItems) {
    const uint32_t at = base + threadIdx.x * kPairScanItems;
    uint32_t v[kPairScanItems];
    for (uint32_t k = 0; k < kPairScanItems; ++k) v[k] = at + k < job.n ? job.in[at + k] : 0u;
    uint32_t total = 0;
    Scan(storage).ExclusiveSum(v, v, total);
    for (uint32_t k = 0; k < kPairScanItems; ++k)
      if (at + k < job.n) job.out[at + k] = carry + v[k];
    carry += total;
    __syncthreads();  // the storage is used again by the next tile
  }
}

}  // namespace

void CudaExec::exclusive_scan_pair(const uint32_t* in0, uint32_t* out0, size_t n0, const uint32_t* in1,
                                   uint32_t* out1, size_t n1, void* temp, size_t temp_bytes) const {
  if (std::max(n0, n1) > kPairScanBlockMax) {
    exclusive_scan(in0, out0, n0, temp, temp_bytes);
    exclusive_scan(in1, out1, n1, temp, temp_bytes);
    return;
  }
  if (n0 + n1 == 0) return;
  launch(pair_scan_kernel, 2, kPairScanThreads, 0, ScanJob{in0, out0, uint32_t(n0)}, ScanJob{in1, out1, uint32_t(n1)});
}

size_t CudaExec::sort_temp_bytes(size_t n) const {
  size_t bytes = 0;
  cuda_check(cub::DeviceRadixSort::SortPairs(nullptr, bytes, static_cast<const uint64_t*>(nullptr),
                                             static_cast<uint64_t*>(nullptr),
                                             static_cast<const uint32_t*>(nullptr),
                                             static_cast<uint32_t*>(nullptr), int64_t(n), 0, 64,
                                             stream_),
             "sort size query");
  return bytes;
}

void CudaExec::sort_pairs(const uint64_t* keys_in, uint64_t* keys_out, const uint32_t* values_in,
                          uint32_t* values_out, size_t n, int end_bit, void* temp,
                          size_t temp_bytes) const {
  if (n == 0) return;
  cuda_check(cub::DeviceRadixSort::SortPairs(temp, temp_bytes, keys_in, keys_out, values_in,
                                             values_out, int64_t(n), 0, end_bit, stream_),
             "radix sort");
}

void CudaExec::sync() const {
  ++host_syncs_;
  cuda_check(cudaStreamSynchronize(stream_), "stream sync");
}

void CudaExec::copy_to_host_bytes(void* dst, const void* src, size_t bytes) const {
  if (!bytes) return;
  cuda_check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, stream_), "copy to host");
  sync();
}

void CudaExec::copy_from_host_bytes(void* dst, const void* src, size_t bytes) const {
  if (!bytes) return;
  cuda_check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, stream_), "copy to device");
}

void CudaExec::copy_bytes(void* dst, const void* src, size_t bytes) const {
  if (!bytes) return;
  cuda_check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToDevice, stream_), "device copy");
}

CudaPhaseTimer::CudaPhaseTimer(CudaExec& exec, bool phases) : exec_(&exec), phases_(phases), stream_(exec.stream()) {
  cuda_check(cudaEventCreate(&frame_begin_), "event creation");
  cuda_check(cudaEventCreate(&frame_end_), "event creation");
}

CudaPhaseTimer::~CudaPhaseTimer() {
  for (auto e : pool_) cudaEventDestroy(e);
  cudaEventDestroy(frame_begin_);
  cudaEventDestroy(frame_end_);
}

cudaEvent_t CudaPhaseTimer::next_event() {
  if (used_ == pool_.size()) {
    cudaEvent_t e;
    cuda_check(cudaEventCreate(&e), "event creation");
    pool_.push_back(e);
  }
  return pool_[used_++];
}

// While a graph is captured, an event record must become a node of the graph (external
// event) rather than a dependency marker, or the replay would not time anything.
void CudaPhaseTimer::record(cudaEvent_t e) {
  cuda_check(cudaEventRecordWithFlags(e, stream_, recording_ ? cudaEventRecordExternal : cudaEventRecordDefault),
             "event record");
}

void CudaPhaseTimer::start(Phase p) {
  if (!timed(p)) return;
  cudaEvent_t e = next_event();
  record(e);
  open_[size_t(p)] = e;
}

void CudaPhaseTimer::stop(Phase p) {
  if (!timed(p)) return;
  cudaEvent_t e = next_event();
  record(e);
  spans_.push_back({p, open_[size_t(p)], e});
}

void CudaPhaseTimer::begin_recording() {
  recording_ = true;
  recording_first_event_ = used_;
  recording_first_span_ = spans_.size();
}

CudaPhaseTimer::Recording CudaPhaseTimer::end_recording() {
  recording_ = false;
  Recording r;
  r.first_event = recording_first_event_;
  r.end_event = used_;
  r.spans.assign(spans_.begin() + std::ptrdiff_t(recording_first_span_), spans_.end());
  return r;
}

bool CudaPhaseTimer::replay(const Recording& r) {
  if (used_ != r.first_event || r.end_event > pool_.size()) return false;
  used_ = r.end_event;
  spans_.insert(spans_.end(), r.spans.begin(), r.spans.end());
  return true;
}

CudaFrameGraph::~CudaFrameGraph() {
  for (Slot& s : slots_)
    if (s.graph_exec) cudaGraphExecDestroy(s.graph_exec);
}

void CudaFrameGraph::begin_capture(CudaExec& exec, CudaPhaseTimer& timer, Slot& s) {
  s.valid = false;
  cuda_check(cudaStreamBeginCapture(exec.stream(), cudaStreamCaptureModeThreadLocal), "graph capture begin");
  timer.begin_recording();
}

void CudaFrameGraph::abandon_capture(CudaExec& exec, CudaPhaseTimer& timer) {
  timer.end_recording();
  cudaGraph_t graph = nullptr;
  cudaStreamEndCapture(exec.stream(), &graph);
  if (graph) cudaGraphDestroy(graph);
}

void CudaFrameGraph::end_capture(CudaExec& exec, CudaPhaseTimer& timer, Slot& s) {
  s.recording = timer.end_recording();
  cudaGraph_t graph = nullptr;
  cuda_check(cudaStreamEndCapture(exec.stream(), &graph), "graph capture end");
  if (s.graph_exec) {
    cudaGraphExecUpdateResultInfo info{};
    if (cudaGraphExecUpdate(s.graph_exec, graph, &info) == cudaSuccess) {
      cudaGraphDestroy(graph);
      return;
    }
    cudaGetLastError();  // a refused update is not an error: instantiate anew
    cudaGraphExecDestroy(s.graph_exec);
    s.graph_exec = nullptr;
  }
  const cudaError_t status = cudaGraphInstantiate(&s.graph_exec, graph, 0);
  cudaGraphDestroy(graph);
  cuda_check(status, "graph instantiation");
}

void CudaFrameGraph::launch_graph(CudaExec& exec, const Slot& s) {
  cuda_check(cudaGraphLaunch(s.graph_exec, exec.stream()), "graph launch");
}

void CudaPhaseTimer::start_frame() {
  used_ = 0;
  spans_.clear();
  syncs_at_start_ = exec_->host_syncs();
  cuda_check(cudaEventRecord(frame_begin_, stream_), "event record");
}

void CudaPhaseTimer::stop_frame() {
  cuda_check(cudaEventRecord(frame_end_, stream_), "event record");
}

double CudaPhaseTimer::phase_ms(Phase p) const {
  double total = 0.0;
  for (const auto& s : spans_) {
    if (s.phase != p) continue;
    float ms = 0.0f;
    cuda_check(cudaEventElapsedTime(&ms, s.begin, s.end), "event timing");
    total += ms;
  }
  return total;
}

double CudaPhaseTimer::frame_ms() const {
  float ms = 0.0f;
  cuda_check(cudaEventElapsedTime(&ms, frame_begin_, frame_end_), "event timing");
  return ms;
}

}  // namespace cdb
