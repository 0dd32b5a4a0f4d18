#pragma once
// Measurement aids of a backend, for the frame loop to use between frames, never inside a
// timed one: evicting the caches before a frame (--cold, nvbench's cold measurement), the
// device's copy bandwidth, the yardstick that achieved traffic is reported against, and the
// GPU's conditions (clocks, temperature, power, clock limits) around the measured frames.
#include <memory>
#include <string>

#include "cdbench/pipeline/gpu_conditions.h"

namespace cdb {

class DeviceProbe {
 public:
  virtual ~DeviceProbe() = default;
  // Allocates flush_caches()'s buffer, twice the size of the last-level cache (the GPU's L2,
  // the CPU's L3): once, before the frames, and only for a run that flushes (--cold). On a
  // server CPU that is hundreds of MB to fill, too much to spend on every run.
  virtual void reserve_cache_flush() = 0;
  // Overwrites that buffer and waits for it, so the next frame starts with none of its data
  // cached; fails where reserve_cache_flush() was not called.
  virtual void flush_caches() = 0;
  // Copy bandwidth in GB/s, counting bytes read plus bytes written: the best of several
  // large device-to-device copies (host: memcpy on one thread). Allocates and frees its
  // buffers; call it once per run, before the frames.
  virtual double copy_bandwidth_gbps() = 0;
  // The GPU's conditions now (NVML, nvml_reader.h); absent with the reason on the host
  // executor and where NVML is not there.
  virtual GpuReading gpu_conditions() = 0;
};

// For --device cuda or cpu (fails like make_pipeline on an unknown or absent device).
std::unique_ptr<DeviceProbe> make_device_probe(const std::string& device);

// The CUDA backend's (cuda_probe.cu, or cuda_probe_absent.cpp without CUDA).
std::unique_ptr<DeviceProbe> make_cuda_probe();

}  // namespace cdb
