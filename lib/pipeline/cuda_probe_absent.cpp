// Compiled instead of cuda_probe.cu when the build found no CUDA compiler.
#include "cdbench/core/error.h"
#include "cdbench/pipeline/device_probe.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

CudaDeviceInfo cuda_device_info() {
  CudaDeviceInfo info;
  info.reason = "built without CUDA";
  return info;
}

std::unique_ptr<DeviceProbe> make_cuda_probe() {
  fail("--device cuda: this cdbench was built without CUDA (no nvcc found at configure time)");
}

}  // namespace cdb
