// The CUDA backend's measurement aids (device_probe.h) and device query (pipeline.h).
#include <algorithm>
#include <memory>
#include <string>

#include "cdbench/core/error.h"
#include "cdbench/exec/cuda_exec.cuh"
#include "cdbench/pipeline/device_probe.h"
#include "cdbench/pipeline/nvml_reader.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

namespace {

// Buffers are allocated here, once per run, outside every timed frame.
class CudaProbe final : public DeviceProbe {
 public:
  CudaProbe() {
    int device = 0, l2 = 0;
    cuda_check(cudaGetDevice(&device), "device query");
    cuda_check(cudaDeviceGetAttribute(&l2, cudaDevAttrL2CacheSize, device), "L2 size query");
    // NVML numbers devices its own way: the run's device is the one on its PCI bus.
    char bus_id[32] = {};
    cuda_check(cudaDeviceGetPCIBusId(bus_id, int(sizeof bus_id), device), "PCI bus id query");
    nvml_ = std::make_unique<NvmlReader>(bus_id);
    l2_bytes_ = size_t(std::max(l2, 1 << 20));
  }
  ~CudaProbe() override { cudaFree(flush_); }
  CudaProbe(const CudaProbe&) = delete;
  CudaProbe& operator=(const CudaProbe&) = delete;

  void reserve_cache_flush() override {
    if (flush_) return;
    flush_bytes_ = 2 * l2_bytes_;
    cuda_check(cudaMalloc(&flush_, flush_bytes_), "cache flush buffer");
  }

  void flush_caches() override {
    if (!flush_) fail("cache flush: reserve_cache_flush() was not called before the frames");
    ++fill_;
    cuda_check(cudaMemsetAsync(flush_, fill_, flush_bytes_, nullptr), "cache flush");
    cuda_check(cudaDeviceSynchronize(), "cache flush");
  }

  double copy_bandwidth_gbps() override {
    const size_t bytes = size_t(1) << 30;
    void *src = nullptr, *dst = nullptr;
    cuda_check(cudaMalloc(&src, bytes), "bandwidth buffer");
    cuda_check(cudaMalloc(&dst, bytes), "bandwidth buffer");
    cudaEvent_t begin, end;
    cuda_check(cudaEventCreate(&begin), "event creation");
    cuda_check(cudaEventCreate(&end), "event creation");
    cuda_check(cudaMemsetAsync(src, 1, bytes, nullptr), "bandwidth buffer");
    float best_ms = 0.0f;
    for (int k = 0; k < 6; ++k) {  // the first copy warms up and is not counted
      cuda_check(cudaEventRecord(begin, nullptr), "event record");
      cuda_check(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToDevice, nullptr), "bandwidth copy");
      cuda_check(cudaEventRecord(end, nullptr), "event record");
      cuda_check(cudaEventSynchronize(end), "bandwidth copy");
      float ms = 0.0f;
      cuda_check(cudaEventElapsedTime(&ms, begin, end), "event timing");
      if (k > 0 && (best_ms == 0.0f || ms < best_ms)) best_ms = ms;
    }
    cudaEventDestroy(begin);
    cudaEventDestroy(end);
    cudaFree(src);
    cudaFree(dst);
    return 2.0 * double(bytes) / (double(best_ms) * 1e-3) / 1e9;
  }

  GpuReading gpu_conditions() override { return nvml_->read(); }

 private:
  void* flush_ = nullptr;
  size_t flush_bytes_ = 0;
  size_t l2_bytes_ = 0;
  unsigned char fill_ = 0;
  std::unique_ptr<NvmlReader> nvml_;
};

// Why no device can run, in the user's terms: the runtime's own text ("CUDA driver version
// is insufficient for CUDA runtime version") reads as a version mismatch on a machine that
// has no NVIDIA driver at all, which is the common case.
std::string no_device_reason(cudaError_t status, int count) {
  int runtime = 0;
  cudaRuntimeGetVersion(&runtime);
  const std::string built = std::to_string(runtime / 1000) + "." + std::to_string(runtime % 1000 / 10);
  switch (status) {
    case cudaSuccess:
      return count == 0 ? "no CUDA device" : "";
    case cudaErrorInsufficientDriver:
      return "no usable NVIDIA driver: none is installed, or it is older than this build's CUDA " + built +
             " runtime";
    case cudaErrorNoDevice:
      return "no CUDA device (the NVIDIA driver finds none)";
    default:
      return std::string("no usable CUDA device (") + cudaGetErrorString(status) + ")";
  }
}

}  // namespace

std::unique_ptr<DeviceProbe> make_cuda_probe() {
  const CudaDeviceInfo info = cuda_device_info();
  if (!info.available) fail("--device cuda: " + info.reason);
  return std::make_unique<CudaProbe>();
}

CudaDeviceInfo cuda_device_info() {
  CudaDeviceInfo info;
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess || count == 0) {
    info.reason = no_device_reason(status, count);
    return info;
  }
  cudaDeviceProp prop{};
  cuda_check(cudaGetDeviceProperties(&prop, 0), "device query");
  info.available = true;
  info.device_count = count;
  info.name = prop.name;
  info.total_bytes = prop.totalGlobalMem;
  cudaDriverGetVersion(&info.driver_version);
  cudaRuntimeGetVersion(&info.runtime_version);
  return info;
}

}  // namespace cdb
