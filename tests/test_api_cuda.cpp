// The public API's CUDA paths (label gpu): frames from device memory the caller owns, written
// on the caller's stream, read in place; the pairs in device memory. Skipped without a GPU.
#include <cuda_runtime.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "api_cloth.h"
#include "cdbench/cdbench.h"

namespace {

constexpr uint32_t kSide = 16;

#define CUDA_OK(call) ASSERT_EQ((call), cudaSuccess) << #call

cdbench::Topology cloth() { return cdb::test::api_cloth(kSide); }
std::vector<float> waving(int frame) { return cdb::test::api_cloth_waving(kSide, frame); }

bool same(std::vector<cdbench::Pair> a, const std::vector<cdbench::Pair>& b) {
  std::sort(a.begin(), a.end(), [](auto x, auto y) { return cdb::pair_key(x) < cdb::pair_key(y); });
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](auto x, auto y) {
           return cdb::pair_key(x) == cdb::pair_key(y);
         });
}

TEST(ApiCuda, DeviceFramesOnTheCallersStreamEqualTheOracle) {
  std::string reason;
  if (!cdbench::cuda_available(&reason)) GTEST_SKIP() << reason;
  const cdbench::Topology topology = cloth();
  const size_t n = topology.num_vertices;
  cudaStream_t stream;
  CUDA_OK(cudaStreamCreateWithFlags(&stream, cudaStreamNonBlocking));
  float* device = nullptr;
  CUDA_OK(cudaMalloc(&device, 3 * n * sizeof(float)));
  for (const char* name : {"c", "bvh", "sweep", "grid"})
    for (bool swept : {false, true}) {
      cdbench::BroadPhase bp({.pipeline = name, .executor = "cuda", .skip_adjacent = true, .swept = swept}, topology);
      std::vector<float> previous;
      for (int f = 0; f < 5; ++f) {
        const std::vector<float> xyz = waving(f);
        // Written on the caller's stream and not waited for: the frame must wait on the device.
        CUDA_OK(cudaMemcpyAsync(device, xyz.data(), xyz.size() * sizeof(float), cudaMemcpyHostToDevice, stream));
        const cdbench::FrameStats& s = bp.run_device(device, n, stream);
        const std::vector<cdbench::Pair> pairs = bp.pairs();
        const std::vector<cdbench::Pair> exact = cdbench::oracle_pairs(topology, xyz.data(), n, true);
        if (!swept) {
          EXPECT_TRUE(same(pairs, exact)) << name << " frame " << f;
        } else {
          // Swept boxes: the pairs of the same frames uploaded from the host.
          cdbench::BroadPhase host({.pipeline = name, .executor = "cuda", .skip_adjacent = true, .swept = true},
                                   topology);
          if (!previous.empty()) host.run(previous.data(), n);
          host.run(xyz.data(), n);
          EXPECT_TRUE(same(pairs, host.pairs())) << name << " swept frame " << f;
        }
        EXPECT_EQ(s.pairs, pairs.size());
        const cdbench::DevicePairs d = bp.device_pairs();
        ASSERT_EQ(d.count, pairs.size());
        std::vector<cdbench::Pair> downloaded(d.count);
        CUDA_OK(cudaMemcpy(downloaded.data(), d.data, d.count * sizeof(cdbench::Pair), cudaMemcpyDeviceToHost));
        EXPECT_TRUE(same(downloaded, pairs)) << name << " frame " << f;
        previous = xyz;
      }
    }
  CUDA_OK(cudaFree(device));
  CUDA_OK(cudaStreamDestroy(stream));
}

}  // namespace
