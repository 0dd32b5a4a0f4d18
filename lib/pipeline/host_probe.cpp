#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <memory>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/pipeline/device_probe.h"

namespace cdb {
namespace {

size_t last_level_cache_bytes() {
  const long l3 = sysconf(_SC_LEVEL3_CACHE_SIZE);
  const long l2 = sysconf(_SC_LEVEL2_CACHE_SIZE);
  const long best = std::max(l3, l2);
  return best > 0 ? size_t(best) : size_t(32) << 20;
}

class HostProbe final : public DeviceProbe {
 public:
  void reserve_cache_flush() override { flush_.resize(2 * last_level_cache_bytes()); }

  void flush_caches() override {
    if (flush_.empty()) fail("cache flush: reserve_cache_flush() was not called before the frames");
    ++fill_;
    std::memset(flush_.data(), fill_, flush_.size());
    // Read one byte per line back through a volatile so the stores cannot be dropped.
    volatile unsigned char sink = 0;
    for (size_t i = 0; i < flush_.size(); i += 64) sink = sink + flush_[i];
  }

  double copy_bandwidth_gbps() override {
    const size_t bytes = size_t(64) << 20;  // twice that in all: past any last-level cache
    // dst is left unfilled: the first copy touches its pages, and the best of three is kept.
    const std::unique_ptr<unsigned char[]> dst(new unsigned char[bytes]);
    std::vector<unsigned char> src(bytes, 1);
    double best = 0.0;
    for (int k = 0; k < 3; ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      std::memcpy(dst.get(), src.data(), bytes);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (dst[bytes / 2] != 1) fail("copy bandwidth: memcpy produced wrong data");
      best = std::max(best, 2.0 * double(bytes) / s / 1e9);
    }
    return best;
  }

  GpuReading gpu_conditions() override { return absent_gpu_reading("host executor (--device cpu): no GPU in use"); }

 private:
  std::vector<unsigned char> flush_;
  unsigned char fill_ = 0;
};

}  // namespace

std::unique_ptr<DeviceProbe> make_device_probe(const std::string& device) {
  if (device == "cpu") return std::make_unique<HostProbe>();
  if (device == "cuda") return make_cuda_probe();
  fail("unknown device '" + device + "' (known: cuda, cpu)");
}

}  // namespace cdb
