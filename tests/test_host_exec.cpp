// The host executor's scan and radix sort against plain serial references, on awkward
// sizes (empty, one, primes, just past the executor's chunk sizes, 2^20 + 3) and keys
// (all equal, descending, few distinct, bits above the sorted ones), at several thread
// counts: the results must be the same bits whatever the threads.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "cdbench/exec/host_exec.h"
#include "scan_cases.h"
#include "tile_cases.h"

namespace cdb {
namespace {

std::vector<size_t> awkward_sizes() {
  return {0,
          1,
          2,
          3,
          97,
          2047,
          2049,
          kSortChunkKeys - 1,
          kSortChunkKeys + 1,
          (size_t(1) << 15) + 1,
          65521,
          (size_t(1) << 20) + 3};
}

// Thread counts to run each case at: one, an odd count, and OpenMP's default.
std::vector<int> thread_counts() { return {1, 3, omp_get_max_threads()}; }

class Threads {
 public:
  explicit Threads(int n) : saved_(omp_get_max_threads()) { omp_set_num_threads(n); }
  ~Threads() { omp_set_num_threads(saved_); }

 private:
  int saved_;
};

std::vector<uint32_t> serial_exclusive_scan(const std::vector<uint32_t>& in) {
  std::vector<uint32_t> out(in.size());
  uint32_t sum = 0;
  for (size_t i = 0; i < in.size(); ++i) {
    out[i] = sum;
    sum += in[i];
  }
  return out;
}

TEST(HostExecScan, MatchesTheSerialScan) {
  HostExec exec;
  std::mt19937 rng(7);
  for (size_t n : awkward_sizes()) {
    // Large values wrap the 32-bit sum: the chunked scan must wrap the same way.
    for (uint32_t limit : {1u, 0xFFFFFFFFu}) {
      std::vector<uint32_t> in(n);
      for (uint32_t& v : in) v = uint32_t(rng()) % (limit + uint64_t(1));
      const std::vector<uint32_t> expected = serial_exclusive_scan(in);
      std::vector<uint8_t> temp(exec.scan_temp_bytes(n));
      for (int threads : thread_counts()) {
        Threads t(threads);
        std::vector<uint32_t> out(n, 0xDEADBEEFu);
        exec.exclusive_scan(in.data(), out.data(), n, temp.data(), temp.size());
        ASSERT_EQ(out, expected) << "n " << n << ", threads " << threads << ", limit " << limit;
        std::vector<uint32_t> in_place = in;
        exec.exclusive_scan(in_place.data(), in_place.data(), n, temp.data(), temp.size());
        ASSERT_EQ(in_place, expected) << "in place, n " << n << ", threads " << threads;
      }
    }
  }
}

TEST(HostExecScan, PairMatchesTheSerialScans) { check_exclusive_scan_pair<HostExec>(); }

TEST(HostExecTiles, EveryIndexOnceInItsTile) { check_for_each_tile<HostExec>(); }

TEST(HostExecScan, RefusesTooLittleTemporaryStorage) {
  HostExec exec;
  std::vector<uint32_t> in(1 << 16, 1), out(in.size());
  ASSERT_GT(exec.scan_temp_bytes(in.size()), 0u);
  std::vector<uint8_t> temp(exec.scan_temp_bytes(in.size()) - 1);
  EXPECT_THROW(exec.exclusive_scan(in.data(), out.data(), in.size(), temp.data(), temp.size()), Error);
}

enum class Keys { random, all_equal, descending, few_distinct, high_bits_only, two_runs };

const char* keys_name(Keys k) {
  switch (k) {
    case Keys::random: return "random";
    case Keys::all_equal: return "all equal";
    case Keys::descending: return "descending";
    case Keys::few_distinct: return "few distinct";
    case Keys::high_bits_only: return "high bits only";
    case Keys::two_runs: return "two runs of bits";
  }
  return "?";
}

std::vector<uint64_t> make_keys(Keys kind, size_t n, std::mt19937_64& rng) {
  std::vector<uint64_t> keys(n);
  for (size_t i = 0; i < n; ++i) {
    switch (kind) {
      case Keys::random: keys[i] = rng(); break;
      case Keys::all_equal: keys[i] = 0x123456789ABCDEF0ull; break;
      case Keys::descending: keys[i] = ~uint64_t(0) - uint64_t(i) * 0x9E3779B9ull; break;
      case Keys::few_distinct: keys[i] = (rng() % 5) << 40 | (rng() % 3); break;
      // Keys that differ only above bit 40: a sort on fewer bits must keep their order.
      case Keys::high_bits_only: keys[i] = (rng() << 40) | 0x5A5A5ull; break;
      // Two indices below 20000 side by side, as pair_key makes them.
      case Keys::two_runs: keys[i] = (rng() % 20000) << 32 | (rng() % 20000); break;
    }
  }
  return keys;
}

// std::stable_sort on the key's bits [0, end_bit): what CUB's SortPairs gives.
void reference_sort(const std::vector<uint64_t>& keys, const std::vector<uint32_t>& values, int end_bit,
                    std::vector<uint64_t>& sorted_keys, std::vector<uint32_t>& sorted_values) {
  const uint64_t mask = end_bit >= 64 ? ~uint64_t(0) : (uint64_t(1) << end_bit) - 1;
  std::vector<size_t> order(keys.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return (keys[a] & mask) < (keys[b] & mask); });
  sorted_keys.resize(keys.size());
  sorted_values.resize(keys.size());
  for (size_t i = 0; i < order.size(); ++i) {
    sorted_keys[i] = keys[order[i]];
    sorted_values[i] = values[order[i]];
  }
}

TEST(HostExecSort, MatchesTheStableSerialSort) {
  HostExec exec;
  std::mt19937_64 rng(11);
  for (size_t n : awkward_sizes())
    for (Keys kind :
         {Keys::random, Keys::all_equal, Keys::descending, Keys::few_distinct, Keys::high_bits_only, Keys::two_runs})
      for (int end_bit : {64, 63, 41, 33, 22, 11, 1, 0}) {
        // 2^20 + 3 at fewer settings: every digit for four kinds of keys, and a last digit
        // cut short (33) for random keys.
        const bool large_case = (end_bit == 64 && kind != Keys::few_distinct && kind != Keys::high_bits_only) ||
                                (end_bit == 33 && kind == Keys::random);
        if (n > (size_t(1) << 16) && !large_case) continue;
        const std::vector<uint64_t> keys = make_keys(kind, n, rng);
        // Values are the input positions: a stability slip shows as a wrong value.
        std::vector<uint32_t> values(n);
        std::iota(values.begin(), values.end(), 0u);
        std::vector<uint64_t> expected_keys;
        std::vector<uint32_t> expected_values;
        reference_sort(keys, values, end_bit, expected_keys, expected_values);
        std::vector<uint8_t> temp(exec.sort_temp_bytes(n));
        for (int threads : thread_counts()) {
          Threads t(threads);
          std::vector<uint64_t> got_keys(n, 0xFEEDull);
          std::vector<uint32_t> got_values(n, 0xFEEDu);
          exec.sort_pairs(keys.data(), got_keys.data(), values.data(), got_values.data(), n, end_bit, temp.data(),
                          temp.size());
          ASSERT_EQ(got_keys, expected_keys)
              << "n " << n << ", " << keys_name(kind) << ", end bit " << end_bit << ", threads " << threads;
          ASSERT_EQ(got_values, expected_values)
              << "n " << n << ", " << keys_name(kind) << ", end bit " << end_bit << ", threads " << threads;
          std::vector<uint64_t> keys_only(n, 0xFEEDull);
          std::vector<uint8_t> keys_temp(exec.sort_keys_temp_bytes(n));
          exec.sort_keys(keys.data(), keys_only.data(), n, end_bit, keys_temp.data(), keys_temp.size());
          ASSERT_EQ(keys_only, expected_keys)
              << "keys only, n " << n << ", " << keys_name(kind) << ", end bit " << end_bit << ", threads " << threads;
        }
      }
}

// Storage sized for a capacity serves every smaller sort (the pipelines size once).
TEST(HostExecSort, TemporaryStorageNeverShrinksWithMoreKeys) {
  HostExec exec;
  size_t last = exec.sort_temp_bytes(0), last_keys = exec.sort_keys_temp_bytes(0);
  for (size_t n = 1; n <= kSortChunks * kSortChunkKeys + 3; n += 997) {
    const size_t bytes = exec.sort_temp_bytes(n), keys_bytes = exec.sort_keys_temp_bytes(n);
    ASSERT_GE(bytes, last) << n;
    ASSERT_GE(keys_bytes, last_keys) << n;
    last = bytes;
    last_keys = keys_bytes;
  }
}

TEST(HostExecSort, RefusesTooLittleTemporaryStorage) {
  HostExec exec;
  std::vector<uint64_t> keys(100, 1), keys_out(100);
  std::vector<uint32_t> values(100, 0), values_out(100);
  std::vector<uint8_t> temp(exec.sort_temp_bytes(keys.size()) - 1);
  EXPECT_THROW(exec.sort_pairs(keys.data(), keys_out.data(), values.data(), values_out.data(), keys.size(), 64,
                               temp.data(), temp.size()),
               Error);
  temp.resize(exec.sort_keys_temp_bytes(keys.size()) - 1);
  EXPECT_THROW(exec.sort_keys(keys.data(), keys_out.data(), keys.size(), 64, temp.data(), temp.size()), Error);
}

// sort_by_pair_key (core/pair_set.h) sorts the pair lists the tests and verify read back.
TEST(SortByPairKey, MatchesStdSort) {
  std::mt19937 rng(13);
  for (size_t n : awkward_sizes()) {
    std::vector<PrimPair> pairs(n);
    // Few distinct first triangles, so many pairs share one; some pairs repeat.
    for (PrimPair& p : pairs) p = make_pair_ordered(rng() % 97, rng() % 5000000);
    for (size_t i = 1; i < n; i += 7) pairs[i] = pairs[i / 2];
    std::vector<PrimPair> expected = pairs;
    std::sort(expected.begin(), expected.end(), [](PrimPair a, PrimPair b) { return pair_key(a) < pair_key(b); });
    sort_by_pair_key(pairs);
    ASSERT_EQ(pairs.size(), expected.size());
    for (size_t i = 0; i < n; ++i)
      ASSERT_EQ(pair_key(pairs[i]), pair_key(expected[i])) << "n " << n << ", position " << i;
  }
}

}  // namespace
}  // namespace cdb
