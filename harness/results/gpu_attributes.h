#pragma once
// The GPU's conditions around the measured frames as root attributes of a results file
// (docs/results-format.md "Root attributes"): one table that the writer, the reader and
// `report --csv` all go through, so a field is named and typed in one place.
#include <functional>
#include <string>
#include <vector>

#include "cdbench/pipeline/gpu_conditions.h"

namespace cdb {

// The two readings of a run: just before its measured passes and right after them.
struct GpuConditions {
  GpuReading before = absent_gpu_reading("not read");
  GpuReading after = absent_gpu_reading("not read");
};

// One attribute: a number (NaN where not read) or a text, taken from the readings.
struct GpuAttribute {
  std::string name;
  bool text = false;
  std::function<double(const GpuConditions&)> number;
  std::function<std::string(const GpuConditions&)> words;
};

// gpu_source (`nvml`, or `absent: <why>`), the card (gpu_name, gpu_driver,
// gpu_pci_bus_id, gpu_slowdown_temperature_c), per reading gpu_<field>_before and _after
// (sm_clock_mhz, mem_clock_mhz, temperature_c, power_w, throttle_reasons) and gpu_warning
// (gpu_poor_conditions of the two, "" when good).
const std::vector<GpuAttribute>& gpu_attributes();

}  // namespace cdb
