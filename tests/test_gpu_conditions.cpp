// The GPU's conditions: which pairs of readings make a run's conditions poor, on synthetic
// readings, and NVML's absence said in words (no GPU is needed).
#include <gtest/gtest.h>

#include "cdbench/pipeline/gpu_conditions.h"
#include "cdbench/pipeline/nvml_reader.h"

namespace cdb {
namespace {

GpuReading steady(double sm_mhz, double temperature_c, uint64_t reasons) {
  GpuReading r;
  r.name = "NVIDIA H200";
  r.sm_clock_mhz = sm_mhz;
  r.mem_clock_mhz = 3201;
  r.temperature_c = temperature_c;
  r.slowdown_temperature_c = 87;
  r.power_w = 250;
  r.throttle_reasons = reasons;
  return r;
}

TEST(GpuConditions, SteadyClocksAreGood) {
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1980, 52, 0)), "");
  // An idle GPU after the frames, or clocks an administrator set, limit nothing the run met.
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1900, 52, kGpuIdle | kApplicationsClocksSetting)), "");
}

TEST(GpuConditions, AClockLimitAfterTheFramesIsPoor) {
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1980, 60, kSwPowerCap | kGpuIdle)),
            "GPU clocks held back after the measured frames (sw_power_cap)");
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1980, 60, kHwThermalSlowdown | kSwThermalSlowdown)),
            "GPU clocks held back after the measured frames (sw_thermal_slowdown,hw_thermal_slowdown)");
  // Before the frames only: the frames may have run unlimited; after is what they met.
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, kSwPowerCap), steady(1980, 50, 0)), "");
}

TEST(GpuConditions, AnSmClockThatMovedByMoreThanTenPercentIsPoor) {
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1785, 50, 0)), "") << "9.8% is within the limit";
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1500, 50, 0)),
            "GPU SM clock changed during the measured frames (1980 to 1500 MHz)");
  EXPECT_EQ(gpu_poor_conditions(steady(1200, 45, 0), steady(1980, 50, 0)),
            "GPU SM clock changed during the measured frames (1200 to 1980 MHz)")
      << "a clock that rose during the frames ran them at two speeds too";
}

TEST(GpuConditions, TheSlowdownTemperatureIsPoorWhereItIsKnown) {
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 45, 0), steady(1980, 87, 0)),
            "GPU at 87 C after the measured frames, at or above its slowdown threshold (87 C)");
  GpuReading unknown = steady(1980, 95, 0);
  unknown.slowdown_temperature_c = std::nan("");
  EXPECT_EQ(gpu_poor_conditions(unknown, unknown), "") << "no threshold read, nothing to compare with";
}

TEST(GpuConditions, ReasonsCombineAndUnreadFieldsDecideNothing) {
  GpuReading hot = steady(1500, 90, kHwSlowdown);
  EXPECT_EQ(gpu_poor_conditions(steady(1980, 88, 0), hot),
            "GPU clocks held back after the measured frames (hw_slowdown); GPU SM clock changed during the measured "
            "frames (1980 to 1500 MHz); GPU at 88 C before the measured frames, at or above its slowdown threshold "
            "(87 C); GPU at 90 C after the measured frames, at or above its slowdown threshold (87 C)");
  GpuReading unread;
  EXPECT_EQ(gpu_poor_conditions(unread, unread), "");
  EXPECT_EQ(gpu_poor_conditions(absent_gpu_reading("host executor"), hot), "") << "no reading, no verdict";
}

TEST(GpuConditions, ThrottleReasonsByName) {
  EXPECT_EQ(throttle_reasons_text(std::nullopt), "");
  EXPECT_EQ(throttle_reasons_text(0), "none");
  EXPECT_EQ(throttle_reasons_text(kGpuIdle), "gpu_idle");
  EXPECT_EQ(throttle_reasons_text(kSwPowerCap | kDisplayClockSetting), "sw_power_cap,display_clock_setting");
  EXPECT_EQ(throttle_reasons_text(kSyncBoost | 0x1000), "sync_boost,0x1000") << "a bit NVML adds later, in hex";
}

TEST(NvmlReader, ADeviceItCannotHaveIsAbsentWithTheReason) {
  // No device has this bus id: without a driver NVML does not load, with one it has no such
  // device; either way the reading says so and reads nothing.
  const NvmlReader nvml("ffff:ff:1f.7");
  const GpuReading r = nvml.read();
  EXPECT_FALSE(r.read());
  EXPECT_EQ(r.absent.rfind("NVML", 0), 0u) << r.absent;
  EXPECT_TRUE(std::isnan(r.sm_clock_mhz));
  EXPECT_FALSE(r.throttle_reasons);
  EXPECT_EQ(r.pci_bus_id, "ffff:ff:1f.7");
}

}  // namespace
}  // namespace cdb
