#pragma once
// The GPU's conditions (gpu_conditions.h) read through NVML, the NVIDIA Management Library
// the driver installs. Loaded at run time (dlopen of libnvidia-ml.so.1), so that cdbench
// builds without NVML's header or library and runs where the driver lacks it; every read
// then says why there is none.
#include <memory>
#include <string>

#include "cdbench/pipeline/gpu_conditions.h"

namespace cdb {

class NvmlReader {
 public:
  // Loads NVML, initializes it and finds the device on `pci_bus_id` (as
  // cudaDeviceGetPCIBusId writes it, e.g. "0000:3B:00.0"): the CUDA device the run uses,
  // whatever order the two libraries number devices in.
  explicit NvmlReader(const std::string& pci_bus_id);
  // Shuts NVML down and unloads it.
  ~NvmlReader();
  NvmlReader(const NvmlReader&) = delete;
  NvmlReader& operator=(const NvmlReader&) = delete;

  // The clocks, temperature, power and clock limits now; absent with the reason where
  // NVML or the device could not be had.
  GpuReading read() const;

 private:
  struct Library;
  std::unique_ptr<Library> nvml_;
};

}  // namespace cdb
