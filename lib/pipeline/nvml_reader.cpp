#include "cdbench/pipeline/nvml_reader.h"

#include <dlfcn.h>

#include <cstring>
#include <utility>

namespace cdb {
namespace {

// NVML's C interface as nvml.h declares it, with the values its API reference documents;
// declared here so that building needs no NVML header.
using NvmlReturn = int;                 // nvmlReturn_t
constexpr NvmlReturn kNvmlSuccess = 0;  // NVML_SUCCESS
struct NvmlDeviceOpaque;
using NvmlDevice = NvmlDeviceOpaque*;   // nvmlDevice_t
constexpr int kNvmlClockSm = 1;         // nvmlClockType_t NVML_CLOCK_SM
constexpr int kNvmlClockMem = 2;        // NVML_CLOCK_MEM
constexpr int kNvmlTemperatureGpu = 0;  // nvmlTemperatureSensors_t NVML_TEMPERATURE_GPU
constexpr int kNvmlThresholdSlowdown = 1;  // nvmlTemperatureThresholds_t NVML_TEMPERATURE_THRESHOLD_SLOWDOWN
constexpr unsigned kNvmlNameBytes = 96;    // NVML_DEVICE_NAME_V2_BUFFER_SIZE
constexpr unsigned kNvmlDriverBytes = 80;  // NVML_SYSTEM_DRIVER_VERSION_BUFFER_SIZE

using InitFn = NvmlReturn (*)();
using ShutdownFn = NvmlReturn (*)();
using ErrorStringFn = const char* (*)(NvmlReturn);
using HandleByPciBusIdFn = NvmlReturn (*)(const char*, NvmlDevice*);
using NameFn = NvmlReturn (*)(NvmlDevice, char*, unsigned);
using DriverVersionFn = NvmlReturn (*)(char*, unsigned);
using ClockFn = NvmlReturn (*)(NvmlDevice, int, unsigned*);
using TemperatureFn = NvmlReturn (*)(NvmlDevice, int, unsigned*);
using ThresholdFn = NvmlReturn (*)(NvmlDevice, int, unsigned*);
using PowerFn = NvmlReturn (*)(NvmlDevice, unsigned*);
using ReasonsFn = NvmlReturn (*)(NvmlDevice, unsigned long long*);

}  // namespace

struct NvmlReader::Library {
  void* handle = nullptr;
  bool initialized = false;
  NvmlDevice device = nullptr;
  std::string absent;  // why there is no reading; "" once the device is found
  GpuReading fixed;    // what does not change during a run: name, driver, bus, slowdown
  ShutdownFn shutdown = nullptr;
  ErrorStringFn error_string = nullptr;
  ClockFn clock = nullptr;
  TemperatureFn temperature = nullptr;
  PowerFn power = nullptr;
  ReasonsFn reasons = nullptr;

  template <class Fn>
  Fn symbol(const char* name) const {
    return reinterpret_cast<Fn>(dlsym(handle, name));
  }
  std::string error_text(NvmlReturn r) const {
    const char* text = error_string ? error_string(r) : nullptr;
    return text ? text : "NVML error " + std::to_string(r);
  }
  // A value NVML gives as unsigned, NaN where it would not.
  template <class Query>
  static double value(Query query) {
    unsigned v = 0;
    return query(&v) == kNvmlSuccess ? double(v) : std::nan("");
  }
};

NvmlReader::NvmlReader(const std::string& pci_bus_id) : nvml_(std::make_unique<Library>()) {
  Library& n = *nvml_;
  n.fixed.pci_bus_id = pci_bus_id;
  n.handle = dlopen("libnvidia-ml.so.1", RTLD_NOW | RTLD_LOCAL);
  if (!n.handle) {
    const char* why = dlerror();
    n.absent = std::string("NVML not loaded (") + (why ? why : "libnvidia-ml.so.1 not found") + ")";
    return;
  }
  const auto init = n.symbol<InitFn>("nvmlInit_v2");
  const auto by_bus = n.symbol<HandleByPciBusIdFn>("nvmlDeviceGetHandleByPciBusId_v2");
  const auto name = n.symbol<NameFn>("nvmlDeviceGetName");
  const auto driver = n.symbol<DriverVersionFn>("nvmlSystemGetDriverVersion");
  const auto threshold = n.symbol<ThresholdFn>("nvmlDeviceGetTemperatureThreshold");
  n.shutdown = n.symbol<ShutdownFn>("nvmlShutdown");
  n.error_string = n.symbol<ErrorStringFn>("nvmlErrorString");
  n.clock = n.symbol<ClockFn>("nvmlDeviceGetClockInfo");
  n.temperature = n.symbol<TemperatureFn>("nvmlDeviceGetTemperature");
  n.power = n.symbol<PowerFn>("nvmlDeviceGetPowerUsage");
  // Renamed in NVML 12.2 ("clocks event reasons"); drivers before it have the old name only.
  n.reasons = n.symbol<ReasonsFn>("nvmlDeviceGetCurrentClocksEventReasons");
  if (!n.reasons) n.reasons = n.symbol<ReasonsFn>("nvmlDeviceGetCurrentClocksThrottleReasons");
  const std::pair<const char*, bool> needed[] = {
      {"nvmlInit_v2", init != nullptr},         {"nvmlDeviceGetHandleByPciBusId_v2", by_bus != nullptr},
      {"nvmlShutdown", n.shutdown != nullptr},  {"nvmlDeviceGetClockInfo", n.clock != nullptr},
      {"nvmlDeviceGetTemperature", n.temperature != nullptr}, {"nvmlDeviceGetPowerUsage", n.power != nullptr},
      {"nvmlDeviceGetCurrentClocksThrottleReasons", n.reasons != nullptr}};
  for (const auto& [function, found] : needed)
    if (!found) {
      n.absent = std::string("NVML lacks ") + function;
      return;
    }
  if (const NvmlReturn r = init(); r != kNvmlSuccess) {
    n.absent = "NVML did not start: " + n.error_text(r);
    return;
  }
  n.initialized = true;
  if (const NvmlReturn r = by_bus(pci_bus_id.c_str(), &n.device); r != kNvmlSuccess) {
    n.absent = "NVML has no device at PCI bus id " + pci_bus_id + ": " + n.error_text(r);
    return;
  }
  char text[kNvmlNameBytes > kNvmlDriverBytes ? kNvmlNameBytes : kNvmlDriverBytes] = {};
  if (name && name(n.device, text, kNvmlNameBytes) == kNvmlSuccess) n.fixed.name = text;
  std::memset(text, 0, sizeof text);
  if (driver && driver(text, kNvmlDriverBytes) == kNvmlSuccess) n.fixed.driver = text;
  if (threshold)
    n.fixed.slowdown_temperature_c =
        Library::value([&](unsigned* v) { return threshold(n.device, kNvmlThresholdSlowdown, v); });
}

NvmlReader::~NvmlReader() {
  if (nvml_->initialized) nvml_->shutdown();
  if (nvml_->handle) dlclose(nvml_->handle);
}

GpuReading NvmlReader::read() const {
  const Library& n = *nvml_;
  if (!n.absent.empty()) {
    GpuReading r = absent_gpu_reading(n.absent);
    r.pci_bus_id = n.fixed.pci_bus_id;
    return r;
  }
  GpuReading r = n.fixed;
  r.sm_clock_mhz = Library::value([&](unsigned* v) { return n.clock(n.device, kNvmlClockSm, v); });
  r.mem_clock_mhz = Library::value([&](unsigned* v) { return n.clock(n.device, kNvmlClockMem, v); });
  r.temperature_c = Library::value([&](unsigned* v) { return n.temperature(n.device, kNvmlTemperatureGpu, v); });
  // NVML gives milliwatts.
  r.power_w = Library::value([&](unsigned* v) { return n.power(n.device, v); }) / 1000.0;
  unsigned long long mask = 0;
  if (n.reasons(n.device, &mask) == kNvmlSuccess) r.throttle_reasons = uint64_t(mask);
  return r;
}

}  // namespace cdb
