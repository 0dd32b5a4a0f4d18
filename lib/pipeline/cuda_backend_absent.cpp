// Compiled instead of cuda_backend.cu when the build found no CUDA compiler.
#include "core/error.h"
#include "pipeline/device_probe.h"
#include "pipeline/pipeline.h"

namespace cdb {

std::unique_ptr<Pipeline> make_cuda_pipeline(const PipelineConfig&) {
  fail("--device cuda: this cdbench was built without CUDA (no nvcc found at configure time)");
}

CudaDeviceInfo cuda_device_info() {
  CudaDeviceInfo info;
  info.reason = "built without CUDA";
  return info;
}

std::unique_ptr<DeviceProbe> make_cuda_probe() {
  fail("--device cuda: this cdbench was built without CUDA (no nvcc found at configure time)");
}

}  // namespace cdb
