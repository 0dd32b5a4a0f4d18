#pragma once
// Exec::exclusive_scan_pair against a serial scan, on host and CUDA: both arrays of a pair,
// at sizes on both sides of the one-block limit (kPairScanBlockMax, exec/tuning.h), one array
// empty, and values whose sums wrap 32 bits.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "cdbench/exec/memory.h"

template <class Exec>
void check_exclusive_scan_pair() {
  constexpr size_t kBlockMax = size_t(1) << 14;
  const std::vector<std::pair<size_t, size_t>> sizes = {
      {0, 0}, {1, 0}, {0, 5}, {1, 1}, {1023, 4097}, {4096, 4095}, {9000, 9001}, {kBlockMax, 17}, {kBlockMax + 1, 3},
      {200000, kBlockMax}};
  std::mt19937 rng(5);
  for (const auto& [n0, n1] : sizes)
    for (uint32_t limit : {3u, 0xFFFFFFFFu}) {
      std::vector<uint32_t> in[2] = {std::vector<uint32_t>(n0), std::vector<uint32_t>(n1)};
      std::vector<uint32_t> want[2];
      for (int k = 0; k < 2; ++k) {
        uint32_t sum = 0;
        for (uint32_t& v : in[k]) {
          v = uint32_t(rng()) % (limit + uint64_t(1));
          want[k].push_back(sum);
          sum += v;
        }
      }
      Exec exec;
      cdb::Array<uint32_t> din[2], dout[2];
      cdb::Array<std::byte> temp;
      for (int k = 0; k < 2; ++k) {
        din[k].bind(exec.memory(), "scan_in");
        dout[k].bind(exec.memory(), "scan_out");
        din[k].reserve(in[k].size() + 1);
        dout[k].reserve(in[k].size() + 1);
        exec.copy_from_host(din[k].data(), in[k].data(), in[k].size());
      }
      temp.bind(exec.memory(), "scan_temp");
      temp.reserve(std::max<size_t>(exec.scan_temp_bytes(std::max(n0, n1)), 1));
      exec.exclusive_scan_pair(din[0].data(), dout[0].data(), n0, din[1].data(), dout[1].data(), n1, temp.data(),
                               temp.size());
      for (int k = 0; k < 2; ++k) {
        std::vector<uint32_t> got(in[k].size());
        exec.copy_to_host(got.data(), dout[k].data(), got.size());
        ASSERT_EQ(got, want[k]) << "sizes " << n0 << ", " << n1 << ", array " << k << ", values below " << limit;
      }
    }
}
