#pragma once
// The GPU's conditions around a run's measured frames, as NVML reports them (its clocks,
// temperature, power and the reasons its clocks are held back), and what makes them poor:
// a GPU that throttled, changed its clock during the frames or ran at its slowdown
// temperature measured other speeds than the same code on a cool, unthrottled card.
// Read by nvml_reader.h; decided here, in plain host code.
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>

namespace cdb {

// NVML's clocks-event (formerly clocks-throttle) reasons, the bits of the mask
// nvmlDeviceGetCurrentClocksThrottleReasons returns, as nvml.h documents them
// (nvmlClocksThrottleReason*, "Clocks Event Reasons" in the NVML API reference).
inline constexpr uint64_t kGpuIdle = 0x1;                    // nvmlClocksThrottleReasonGpuIdle
inline constexpr uint64_t kApplicationsClocksSetting = 0x2;  // ...ApplicationsClocksSetting
inline constexpr uint64_t kSwPowerCap = 0x4;                 // ...SwPowerCap
inline constexpr uint64_t kHwSlowdown = 0x8;                 // ...HwSlowdown
inline constexpr uint64_t kSyncBoost = 0x10;                 // ...SyncBoost
inline constexpr uint64_t kSwThermalSlowdown = 0x20;         // ...SwThermalSlowdown
inline constexpr uint64_t kHwThermalSlowdown = 0x40;         // ...HwThermalSlowdown
inline constexpr uint64_t kHwPowerBrakeSlowdown = 0x80;      // ...HwPowerBrakeSlowdown
inline constexpr uint64_t kDisplayClockSetting = 0x100;      // ...DisplayClockSetting

// One reading of the GPU. `absent` says why there is none ("" when read); a field NVML
// would not give (a card without a power sensor) is NaN, or an unset mask.
struct GpuReading {
  std::string absent;
  std::string name, driver, pci_bus_id;
  double sm_clock_mhz = std::nan(""), mem_clock_mhz = std::nan("");
  double temperature_c = std::nan(""), slowdown_temperature_c = std::nan("");
  double power_w = std::nan("");
  std::optional<uint64_t> throttle_reasons;

  bool read() const { return absent.empty(); }
};

// A reading that says why there is none.
GpuReading absent_gpu_reading(const std::string& why);

// The reasons of a mask by name, joined by ','  (`gpu_idle,sw_power_cap`); `none` for no
// reason, bits NVML may add later in hex; "" when the mask was not read.
std::string throttle_reasons_text(const std::optional<uint64_t>& mask);

// The SM clock moved by more than this share of its value before the measured frames: the
// frames did not all run at one speed.
inline constexpr double kSmClockChangeShare = 0.10;

// Why the GPU's conditions were poor, from its readings before and after the measured
// frames, joined by "; " ("" when good, and when either reading is absent): a clock limit
// after the frames other than an idle GPU or the applications clocks setting (a power cap,
// a thermal or hardware slowdown), an SM clock that changed by more than
// kSmClockChangeShare, a temperature at or above the card's slowdown threshold (where it
// is readable).
std::string gpu_poor_conditions(const GpuReading& before, const GpuReading& after);

}  // namespace cdb
