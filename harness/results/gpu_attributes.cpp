#include "harness/results/gpu_attributes.h"

namespace cdb {
namespace {

// The card's own fields are the same in both readings; a reading that failed has none.
const GpuReading& card_reading(const GpuConditions& c) { return c.before.read() ? c.before : c.after; }

}  // namespace

const std::vector<GpuAttribute>& gpu_attributes() {
  static const std::vector<GpuAttribute> attributes = [] {
    using C = const GpuConditions&;
    const auto text = [](std::string name, std::function<std::string(C)> words) {
      return GpuAttribute{std::move(name), true, nullptr, std::move(words)};
    };
    const auto number = [](std::string name, std::function<double(C)> value) {
      return GpuAttribute{std::move(name), false, std::move(value), nullptr};
    };
    std::vector<GpuAttribute> a = {
        text("gpu_source",
             [](C c) {
               if (c.before.read() && c.after.read()) return std::string("nvml");
               return "absent: " + (c.before.read() ? c.after.absent : c.before.absent);
             }),
        text("gpu_name", [](C c) { return card_reading(c).name; }),
        text("gpu_driver", [](C c) { return card_reading(c).driver; }),
        text("gpu_pci_bus_id", [](C c) { return card_reading(c).pci_bus_id; }),
        number("gpu_slowdown_temperature_c", [](C c) { return card_reading(c).slowdown_temperature_c; }),
    };
    using Field = double GpuReading::*;
    const std::pair<const char*, Field> fields[] = {{"sm_clock_mhz", &GpuReading::sm_clock_mhz},
                                                    {"mem_clock_mhz", &GpuReading::mem_clock_mhz},
                                                    {"temperature_c", &GpuReading::temperature_c},
                                                    {"power_w", &GpuReading::power_w}};
    for (const auto& [name, field] : fields) {
      a.push_back(number(std::string("gpu_") + name + "_before", [field = field](C c) { return c.before.*field; }));
      a.push_back(number(std::string("gpu_") + name + "_after", [field = field](C c) { return c.after.*field; }));
    }
    a.push_back(text("gpu_throttle_reasons_before", [](C c) { return throttle_reasons_text(c.before.throttle_reasons); }));
    a.push_back(text("gpu_throttle_reasons_after", [](C c) { return throttle_reasons_text(c.after.throttle_reasons); }));
    a.push_back(text("gpu_warning", [](C c) { return gpu_poor_conditions(c.before, c.after); }));
    return a;
  }();
  return attributes;
}

}  // namespace cdb
