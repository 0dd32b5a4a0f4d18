#include "cdbench/core/error.h"
#include "cdbench/exec/cuda_exec.cuh"
#include "registry/pipeline_factory.h"

namespace cdb {

std::unique_ptr<Pipeline> make_cuda_pipeline(const PipelineConfig& config) {
  const CudaDeviceInfo info = cuda_device_info();
  if (!info.available) fail("--device cuda: " + info.reason);
  return make_pipeline_on<CudaExec, CudaPhaseTimer>(config);
}

}  // namespace cdb
