// The narrow-phase tests compiled by nvcc and run on the GPU, where the filters' products may
// be fused into FMAs: the same answers as the exact oracles and as the host, on the same
// degenerate-rich small-integer pairs at every float placement, for the intersection test
// and for proximity (distance <= d, also through the integer similarity of
// proximity_cases.h, whose full-width mantissas make the filters round).
#include <gtest/gtest.h>

#include <cuda_runtime.h>

#include <cstdint>
#include <string>
#include <vector>

#include "cdbench/narrow/proximity.h"
#include "cdbench/narrow/triangle_intersect.h"
#include "narrow_cases.h"
#include "proximity_cases.h"

namespace cdb {
namespace {

__global__ void intersect_pairs(const vec3f* corners, uint32_t n, uint8_t* meet) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const vec3f* c = corners + 6 * size_t(i);
  meet[i] = triangles_intersect(c[0], c[1], c[2], c[3], c[4], c[5]);
}

__global__ void within_pairs(const vec3f* corners, const float* distances, uint32_t n, uint8_t* within) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n) return;
  const vec3f* c = corners + 6 * size_t(i);
  within[i] = triangles_within(c[0], c[1], c[2], c[3], c[4], c[5], distances[i]);
}

void check(cudaError_t e) { ASSERT_EQ(e, cudaSuccess) << cudaGetErrorString(e); }

TEST(NarrowCuda, DeviceAgreesWithOracleAndHost) {
  int devices = 0;
  if (const cudaError_t e = cudaGetDeviceCount(&devices); e != cudaSuccess || devices == 0)
    GTEST_SKIP() << "no GPU here (" << cudaGetErrorString(e) << "); run on the device";
  std::vector<vec3f> corners;
  std::vector<uint8_t> expected;
  for (const int range : {1, 3, 40}) {
    RandomPairs gen(uint64_t(100 + range), range);
    for (int it = 0; it < 40000; ++it) {
      ITri P, Q;
      gen.next(P, Q);
      const bool meet = sat_oracle_intersect(P, Q);
      for (const Placement& p : kPlacements) {
        for (const IVec& v : P) corners.push_back(place(v, p));
        for (const IVec& v : Q) corners.push_back(place(v, p));
        expected.push_back(meet);
      }
    }
  }
  const uint32_t n = uint32_t(expected.size());
  vec3f* d_corners = nullptr;
  uint8_t* d_meet = nullptr;
  check(cudaMalloc(&d_corners, corners.size() * sizeof(vec3f)));
  check(cudaMalloc(&d_meet, n));
  check(cudaMemcpy(d_corners, corners.data(), corners.size() * sizeof(vec3f), cudaMemcpyHostToDevice));
  intersect_pairs<<<(n + 255) / 256, 256>>>(d_corners, n, d_meet);
  check(cudaGetLastError());
  std::vector<uint8_t> got(n);
  check(cudaMemcpy(got.data(), d_meet, n, cudaMemcpyDeviceToHost));
  check(cudaFree(d_corners));
  check(cudaFree(d_meet));
  uint32_t wrong = 0, meets = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const vec3f* c = &corners[6 * size_t(i)];
    const bool host = triangles_intersect(c[0], c[1], c[2], c[3], c[4], c[5]);
    meets += expected[i];
    if (got[i] != expected[i] || host != bool(expected[i])) {
      if (++wrong <= 5)
        ADD_FAILURE() << "pair " << i << ": oracle " << int(expected[i]) << ", device " << int(got[i]) << ", host "
                      << host;
    }
  }
  EXPECT_EQ(wrong, 0u) << "of " << n;
  EXPECT_GT(meets, n / 5);
  EXPECT_LT(meets, n - n / 5);
}

// Random pairs with d = k / 4 at the oracle's decision (k* - 1, k*, k* + 1 for the least k*
// within: ties whenever the distance is k* / 4), plain and through the similarity, at every
// placement: device, host and oracle agree.
TEST(NarrowCuda, ProximityAgreesWithOracleAndHost) {
  int devices = 0;
  if (const cudaError_t e = cudaGetDeviceCount(&devices); e != cudaSuccess || devices == 0)
    GTEST_SKIP() << "no GPU here (" << cudaGetErrorString(e) << "); run on the device";
  std::vector<vec3f> corners;
  std::vector<float> distances;
  std::vector<uint8_t> expected;
  uint32_t ties = 0;
  for (const int range : {1, 3, 10}) {
    RandomPairs gen(uint64_t(200 + range), range);
    std::mt19937_64 rng(uint64_t(300 + range));
    for (int it = 0; it < 6000; ++it) {
      ITri P, Q;
      gen.next(P, Q);
      const int64_t quarters = quarters_near_decision(P, Q, range, rng);
      const ProximityVerdict v = oracle_within(P, Q, quarters);
      for (const bool similar : {false, true}) {
        const ITri A = similar ? similarity(P) : P, B = similar ? similarity(Q) : Q;
        const int64_t scaled = similar ? quarters * kSimilarityScale : quarters;
        for (const Placement& p : kPlacements) {
          for (const IVec& x : A) corners.push_back(place(x, p));
          for (const IVec& x : B) corners.push_back(place(x, p));
          distances.push_back(place_distance(scaled, p));
          expected.push_back(v.within);
          ties += v.tie;
        }
      }
    }
  }
  const uint32_t n = uint32_t(expected.size());
  vec3f* d_corners = nullptr;
  float* d_distances = nullptr;
  uint8_t* d_within = nullptr;
  check(cudaMalloc(&d_corners, corners.size() * sizeof(vec3f)));
  check(cudaMalloc(&d_distances, n * sizeof(float)));
  check(cudaMalloc(&d_within, n));
  check(cudaMemcpy(d_corners, corners.data(), corners.size() * sizeof(vec3f), cudaMemcpyHostToDevice));
  check(cudaMemcpy(d_distances, distances.data(), n * sizeof(float), cudaMemcpyHostToDevice));
  within_pairs<<<(n + 127) / 128, 128>>>(d_corners, d_distances, n, d_within);
  check(cudaGetLastError());
  std::vector<uint8_t> got(n);
  check(cudaMemcpy(got.data(), d_within, n, cudaMemcpyDeviceToHost));
  check(cudaFree(d_corners));
  check(cudaFree(d_distances));
  check(cudaFree(d_within));
  uint32_t wrong = 0, within = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const vec3f* c = &corners[6 * size_t(i)];
    const bool host = triangles_within(c[0], c[1], c[2], c[3], c[4], c[5], distances[i]);
    within += expected[i];
    if (got[i] != expected[i] || host != bool(expected[i])) {
      if (++wrong <= 5)
        ADD_FAILURE() << "pair " << i << ": oracle " << int(expected[i]) << ", device " << int(got[i]) << ", host "
                      << host << ", d " << distances[i];
    }
  }
  EXPECT_EQ(wrong, 0u) << "of " << n;
  EXPECT_GT(ties, n / 5);
  EXPECT_GT(within, n / 2);
  EXPECT_LT(within, n - n / 10);
}

}  // namespace
}  // namespace cdb
