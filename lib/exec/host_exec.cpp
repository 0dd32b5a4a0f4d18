#include "exec/host_exec.h"

#include <algorithm>
#include <vector>

#include "core/error.h"

namespace cdb {

void HostExec::exclusive_scan(const uint32_t* in, uint32_t* out, size_t n, void*, size_t) const {
  uint32_t sum = 0;
  for (size_t i = 0; i < n; ++i) {
    const uint32_t v = in[i];
    out[i] = sum;
    sum += v;
  }
}

void HostExec::sort_pairs(const uint64_t* keys_in, uint64_t* keys_out, const uint32_t* values_in,
                          uint32_t* values_out, size_t n, int end_bit, void* temp,
                          size_t temp_bytes) const {
  if (temp_bytes < sort_temp_bytes(n)) fail("host sort: temporary storage too small");
  auto* tk = static_cast<uint64_t*>(temp);
  auto* tv = reinterpret_cast<uint32_t*>(tk + n);
  std::copy(keys_in, keys_in + n, keys_out);
  std::copy(values_in, values_in + n, values_out);
  constexpr int kDigit = 11;
  constexpr size_t kBuckets = size_t(1) << kDigit;
  std::vector<size_t> offsets(kBuckets);
  uint64_t* src_k = keys_out;
  uint32_t* src_v = values_out;
  uint64_t* dst_k = tk;
  uint32_t* dst_v = tv;
  for (int shift = 0; shift < end_bit; shift += kDigit) {
    std::fill(offsets.begin(), offsets.end(), 0);
    for (size_t i = 0; i < n; ++i) ++offsets[(src_k[i] >> shift) & (kBuckets - 1)];
    size_t sum = 0;
    for (auto& o : offsets) {
      const size_t c = o;
      o = sum;
      sum += c;
    }
    for (size_t i = 0; i < n; ++i) {
      const size_t slot = offsets[(src_k[i] >> shift) & (kBuckets - 1)]++;
      dst_k[slot] = src_k[i];
      dst_v[slot] = src_v[i];
    }
    std::swap(src_k, dst_k);
    std::swap(src_v, dst_v);
  }
  if (src_k != keys_out) {
    std::copy(src_k, src_k + n, keys_out);
    std::copy(src_v, src_v + n, values_out);
  }
}

}  // namespace cdb
