#include "core/error.h"
#include "exec/cuda_exec.cuh"
#include "pipeline/registry.h"

namespace cdb {

std::unique_ptr<Pipeline> make_cuda_pipeline(const PipelineConfig& config) {
  const CudaDeviceInfo info = cuda_device_info();
  if (!info.available) fail("--device cuda: " + info.reason);
  return make_pipeline_on<CudaExec, CudaPhaseTimer>(config);
}

CudaDeviceInfo cuda_device_info() {
  CudaDeviceInfo info;
  int count = 0;
  const cudaError_t status = cudaGetDeviceCount(&count);
  if (status != cudaSuccess || count == 0) {
    info.reason = status != cudaSuccess ? std::string("no usable CUDA device (") +
                                              cudaGetErrorString(status) + ")"
                                        : std::string("no CUDA device");
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
