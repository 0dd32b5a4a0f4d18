#include "cdbench/exec/host_exec.h"

#include <algorithm>
#include <bit>

#include "cdbench/core/error.h"

namespace cdb {

namespace {
// First index of chunk c of n elements split into `chunks` near-equal runs.
size_t chunk_begin(size_t n, size_t chunks, size_t c) { return n * c / chunks; }

// out[i] = run + in[begin] + ... + in[i - 1] for i in [begin, end), on one thread; in and out
// may be the same array.
void serial_scan(const uint32_t* in, uint32_t* out, size_t begin, size_t end, uint32_t run) {
  for (size_t i = begin; i < end; ++i) {
    const uint32_t v = in[i];
    out[i] = run;
    run += v;
  }
}
}  // namespace

void HostExec::exclusive_scan(const uint32_t* in, uint32_t* out, size_t n, void* temp,
                              size_t temp_bytes) const {
  if (temp_bytes < scan_temp_bytes(n)) fail("host scan: temporary storage too small");
  // Below kParallelScanMin (exec/tuning.h) elements one thread: the second pass over the
  // chunks would cost more than it saves.
  if (n < kParallelScanMin) return serial_scan(in, out, 0, n, 0);
  // Sums modulo 2^32 are associative, so chunking gives the serial scan's bits.
  auto* offset = static_cast<uint32_t*>(temp);
  const int64_t chunks = int64_t(kScanChunks);
#pragma omp parallel for schedule(static)
  for (int64_t c = 0; c < chunks; ++c) {
    uint32_t sum = 0;
    const size_t end = chunk_begin(n, kScanChunks, size_t(c) + 1);
    for (size_t i = chunk_begin(n, kScanChunks, size_t(c)); i < end; ++i) sum += in[i];
    offset[c] = sum;
  }
  serial_scan(offset, offset, 0, kScanChunks, 0);
#pragma omp parallel for schedule(static)
  for (int64_t c = 0; c < chunks; ++c)
    serial_scan(in, out, chunk_begin(n, kScanChunks, size_t(c)), chunk_begin(n, kScanChunks, size_t(c) + 1), offset[c]);
}

namespace {
// The radix sort of sort_pairs and sort_keys; kValues: values travel with their keys.
// `temp` holds the per-chunk digit counts (chunks * kSortBuckets), then the second key
// buffer (n), then, with values, the second value buffer (n).
template <bool kValues>
void radix_sort(const uint64_t* keys_in, uint64_t* keys_out, const uint32_t* values_in, uint32_t* values_out,
                size_t n, int end_bit, void* temp) {
  constexpr size_t kBuckets = HostExec::kSortBuckets;
  constexpr int kDigitBits = kSortDigitBits;
  const int64_t count = int64_t(n);
  const size_t chunks = HostExec::sort_chunks(n);
  const bool parallel = chunks > 1;
  const int bits = std::clamp(end_bit, 0, 64);
  const uint64_t sorted_bits = bits == 64 ? ~uint64_t(0) : (uint64_t(1) << bits) - 1;

  // Bits every key shares move nothing: each pass's digit starts at the lowest bit above
  // the last digit where some keys differ (keys often use far fewer bits than end_bit, or
  // two separate runs of bits, as a pair's two indices).
  uint64_t any = 0, all = ~uint64_t(0);
#pragma omp parallel for schedule(static) reduction(| : any) reduction(& : all) if (parallel)
  for (int64_t i = 0; i < count; ++i) {
    any |= keys_in[i];
    all &= keys_in[i];
  }
  const uint64_t differ = (any ^ all) & sorted_bits;
  int shifts[64 / kDigitBits + 1];
  int passes = 0;
  for (int shift = 0; shift < 64 && (differ >> shift) != 0; shift += kDigitBits) {
    shift += std::countr_zero(differ >> shift);
    shifts[passes++] = shift;
  }

  const int64_t chunk_count = int64_t(chunks);
  if (passes == 0) {
#pragma omp parallel for schedule(static) if (parallel)
    for (int64_t c = 0; c < chunk_count; ++c) {
      const size_t begin = chunk_begin(n, chunks, size_t(c)), end = chunk_begin(n, chunks, size_t(c) + 1);
      std::copy(keys_in + begin, keys_in + end, keys_out + begin);
      if constexpr (kValues) std::copy(values_in + begin, values_in + end, values_out + begin);
    }
    return;
  }

  // The per-chunk digit counts first (their alignment), then the second buffers.
  auto* counts = static_cast<size_t*>(temp);
  auto* temp_keys = reinterpret_cast<uint64_t*>(counts + chunks * kBuckets);
  auto* temp_values = reinterpret_cast<uint32_t*>(temp_keys + n);
  const uint64_t* src_k = keys_in;
  const uint32_t* src_v = values_in;
  for (int p = 0; p < passes; ++p) {
    // Alternate buffers so that the last pass writes the outputs.
    const bool to_out = (passes - 1 - p) % 2 == 0;
    uint64_t* dst_k = to_out ? keys_out : temp_keys;
    uint32_t* dst_v = to_out ? values_out : temp_values;
    const int shift = shifts[p];
    const uint64_t mask = (sorted_bits >> shift) & (kBuckets - 1);
    const size_t buckets = size_t(mask) + 1;
#pragma omp parallel for schedule(static) if (parallel)
    for (int64_t c = 0; c < chunk_count; ++c) {
      size_t* h = counts + size_t(c) * kBuckets;
      std::fill(h, h + buckets, size_t(0));
      const size_t end = chunk_begin(n, chunks, size_t(c) + 1);
      for (size_t i = chunk_begin(n, chunks, size_t(c)); i < end; ++i) ++h[(src_k[i] >> shift) & mask];
    }
    // Each chunk's first slot per digit: after every smaller digit, and after the earlier
    // chunks' keys of the same digit (stability).
    size_t sum = 0;
    for (size_t b = 0; b < buckets; ++b)
      for (size_t c = 0; c < chunks; ++c) {
        size_t& h = counts[c * kBuckets + b];
        const size_t k = h;
        h = sum;
        sum += k;
      }
#pragma omp parallel for schedule(static) if (parallel)
    for (int64_t c = 0; c < chunk_count; ++c) {
      size_t* h = counts + size_t(c) * kBuckets;
      const size_t end = chunk_begin(n, chunks, size_t(c) + 1);
      for (size_t i = chunk_begin(n, chunks, size_t(c)); i < end; ++i) {
        const uint64_t k = src_k[i];
        const size_t slot = h[(k >> shift) & mask]++;
        dst_k[slot] = k;
        if constexpr (kValues) dst_v[slot] = src_v[i];
      }
    }
    src_k = dst_k;
    src_v = dst_v;
  }
}
}  // namespace

void HostExec::sort_pairs(const uint64_t* keys_in, uint64_t* keys_out, const uint32_t* values_in,
                          uint32_t* values_out, size_t n, int end_bit, void* temp,
                          size_t temp_bytes) const {
  if (temp_bytes < sort_temp_bytes(n)) fail("host sort: temporary storage too small");
  if (n) radix_sort<true>(keys_in, keys_out, values_in, values_out, n, end_bit, temp);
}

void HostExec::sort_keys(const uint64_t* keys_in, uint64_t* keys_out, size_t n, int end_bit, void* temp,
                         size_t temp_bytes) const {
  if (temp_bytes < sort_keys_temp_bytes(n)) fail("host sort: temporary storage too small");
  if (n) radix_sort<false>(keys_in, keys_out, nullptr, nullptr, n, end_bit, temp);
}

}  // namespace cdb
