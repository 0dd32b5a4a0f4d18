#pragma once
// One frame of float positions in device memory the program owns, on a CUDA stream of its
// own: what a GPU simulator hands the broad phase (BroadPhase::run_device). Allocated once;
// each frame is written into the same memory. device_positions_cuda.cpp implements it; a
// package built without CUDA links device_positions_absent.cpp, whose constructor throws.
#include <cstddef>

class DevicePositions {
 public:
  explicit DevicePositions(size_t num_vertices);
  ~DevicePositions();
  DevicePositions(const DevicePositions&) = delete;
  DevicePositions& operator=(const DevicePositions&) = delete;

  // Copies num_vertices x, y, z triples from the host on the stream and waits for the copy,
  // so that a frame timed next starts with its positions in place.
  void write(const float* host_xyz);
  const float* data() const { return data_; }
  void* stream() const { return stream_; }  // a cudaStream_t

 private:
  size_t num_vertices_ = 0;
  float* data_ = nullptr;
  void* stream_ = nullptr;
};
