#include "device_positions.h"

#include <cuda_runtime.h>

#include <string>

#include "cdbench/cdbench.h"

namespace {

void check(cudaError_t status, const char* what) {
  if (status != cudaSuccess) throw cdbench::Error(std::string(what) + ": " + cudaGetErrorString(status));
}

}  // namespace

DevicePositions::DevicePositions(size_t num_vertices) : num_vertices_(num_vertices) {
  check(cudaMalloc(reinterpret_cast<void**>(&data_), 3 * sizeof(float) * num_vertices), "cudaMalloc");
  cudaStream_t stream = nullptr;
  check(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking), "cudaStreamCreate");
  stream_ = stream;
}

DevicePositions::~DevicePositions() {
  cudaStreamDestroy(static_cast<cudaStream_t>(stream_));
  cudaFree(data_);
}

void DevicePositions::write(const float* host_xyz) {
  const auto stream = static_cast<cudaStream_t>(stream_);
  check(cudaMemcpyAsync(data_, host_xyz, 3 * sizeof(float) * num_vertices_, cudaMemcpyHostToDevice, stream),
        "cudaMemcpyAsync");
  check(cudaStreamSynchronize(stream), "cudaStreamSynchronize");
}
