// The package was built without CUDA: there is no device memory to own.
#include "device_positions.h"

#include "cdbench/cdbench.h"

DevicePositions::DevicePositions(size_t) {
  throw cdbench::Error("device positions need a cdbench package built with CUDA (cdbench_CUDA is off)");
}

DevicePositions::~DevicePositions() = default;

void DevicePositions::write(const float*) {}
