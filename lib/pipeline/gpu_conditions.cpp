#include "cdbench/pipeline/gpu_conditions.h"

#include <cstdio>
#include <utility>

namespace cdb {

GpuReading absent_gpu_reading(const std::string& why) {
  GpuReading r;
  r.absent = why;
  return r;
}

std::string throttle_reasons_text(const std::optional<uint64_t>& mask) {
  if (!mask) return "";
  if (*mask == 0) return "none";
  static constexpr std::pair<uint64_t, const char*> kNames[] = {
      {kGpuIdle, "gpu_idle"},
      {kApplicationsClocksSetting, "applications_clocks_setting"},
      {kSwPowerCap, "sw_power_cap"},
      {kHwSlowdown, "hw_slowdown"},
      {kSyncBoost, "sync_boost"},
      {kSwThermalSlowdown, "sw_thermal_slowdown"},
      {kHwThermalSlowdown, "hw_thermal_slowdown"},
      {kHwPowerBrakeSlowdown, "hw_power_brake_slowdown"},
      {kDisplayClockSetting, "display_clock_setting"}};
  std::string text;
  uint64_t known = 0;
  for (const auto& [bit, name] : kNames) {
    known |= bit;
    if (*mask & bit) text += (text.empty() ? "" : ",") + std::string(name);
  }
  if (*mask & ~known) {
    char rest[32];
    std::snprintf(rest, sizeof rest, "0x%llx", static_cast<unsigned long long>(*mask & ~known));
    text += (text.empty() ? "" : ",") + std::string(rest);
  }
  return text;
}

std::string gpu_poor_conditions(const GpuReading& before, const GpuReading& after) {
  if (!before.read() || !after.read()) return "";
  std::string notes;
  const auto add = [&notes](const std::string& why) { notes += (notes.empty() ? "" : "; ") + why; };
  char text[192];
  // An idle GPU drops its clocks and the applications clocks are a setting, not a limit
  // the run met; every other reason held the clocks below what the code would have run at.
  if (after.throttle_reasons) {
    const uint64_t limits = *after.throttle_reasons & ~(kGpuIdle | kApplicationsClocksSetting);
    if (limits) add("GPU clocks held back after the measured frames (" + throttle_reasons_text(limits) + ")");
  }
  if (before.sm_clock_mhz > 0 && std::isfinite(after.sm_clock_mhz) &&
      std::abs(after.sm_clock_mhz - before.sm_clock_mhz) > kSmClockChangeShare * before.sm_clock_mhz) {
    std::snprintf(text, sizeof text, "GPU SM clock changed during the measured frames (%.0f to %.0f MHz)",
                  before.sm_clock_mhz, after.sm_clock_mhz);
    add(text);
  }
  for (const auto& [r, when] : {std::pair{&before, "before"}, std::pair{&after, "after"}})
    if (r->temperature_c >= r->slowdown_temperature_c) {
      std::snprintf(text, sizeof text, "GPU at %.0f C %s the measured frames, at or above its slowdown threshold (%.0f C)",
                    r->temperature_c, when, r->slowdown_temperature_c);
      add(text);
    }
  return notes;
}

}  // namespace cdb
