// Google Benchmark of the append step every front operation and pair sink does: a thread
// takes one slot of a shared output array and writes it. How many lanes of a warp append
// together varies (the traversals diverge), so each case runs at 32, 8 and 2 active lanes
// a warp. Cases: one counter with warp aggregation (claim_one, as the front sinks use),
// one counter with one atomic per lane, 64 counters striped by block (each owning a
// region), a reduction that returns nothing (count_one, as the count logs use), and plain
// stores at precomputed slots (the floor). Times from CUDA events, manual-time benchmarks.
#include <benchmark/benchmark.h>
#include <cuda_runtime.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "cdbench/core/atomics.h"

namespace {

constexpr uint32_t kStripes = 64;

__device__ bool lane_active(uint32_t i, uint32_t active) { return ((i * 2654435761u) >> 27) < active; }

enum Mode : int { kClaimOne, kPerLane, kStriped, kCountOne, kPlainStore };

__global__ void append_kernel(uint32_t n, uint32_t active, int mode, unsigned long long* counters,
                              uint32_t* out, uint32_t region) {
  const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
  if (i >= n || !lane_active(i, active)) return;
  switch (mode) {
    case kClaimOne:
      out[cdb::claim_one(&counters[0])] = i;
      break;
    case kPerLane:
      out[atomicAdd(&counters[0], 1ull)] = i;
      break;
    case kStriped: {
      const uint32_t s = blockIdx.x % kStripes;
      const unsigned long long slot = cdb::claim_one(&counters[s]);
      if (slot < region) out[size_t(s) * region + slot] = i;
      break;
    }
    case kCountOne:
      cdb::count_one(&counters[0]);
      out[i] = i;
      break;
    case kPlainStore:
      out[i] = i;
      break;
  }
}

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) {
    std::fprintf(stderr, "append_bench: %s: %s\n", what, cudaGetErrorString(e));
    std::exit(1);
  }
}

void append(benchmark::State& state) {
  const uint32_t n = uint32_t(state.range(0));
  const uint32_t active = uint32_t(state.range(1));
  const int mode = int(state.range(2));
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    state.SkipWithError("no CUDA device");
    return;
  }
  unsigned long long* counters = nullptr;
  uint32_t* out = nullptr;
  const uint32_t region = n / kStripes * 2 + 1024;
  check(cudaMalloc(&counters, kStripes * sizeof(unsigned long long)), "cudaMalloc");
  check(cudaMalloc(&out, size_t(region) * kStripes * sizeof(uint32_t)), "cudaMalloc");
  cudaEvent_t start, stop;
  check(cudaEventCreate(&start), "event");
  check(cudaEventCreate(&stop), "event");
  const uint32_t blocks = (n + 255) / 256;
  unsigned long long appended = 0;
  for (auto _ : state) {
    check(cudaMemset(counters, 0, kStripes * sizeof(unsigned long long)), "cudaMemset");
    check(cudaEventRecord(start), "record");
    append_kernel<<<blocks, 256>>>(n, active, mode, counters, out, region);
    check(cudaEventRecord(stop), "record");
    check(cudaEventSynchronize(stop), "synchronize");
    check(cudaGetLastError(), "append_kernel");
    float ms = 0;
    check(cudaEventElapsedTime(&ms, start, stop), "elapsed");
    state.SetIterationTime(double(ms) / 1e3);
    unsigned long long c[kStripes];
    check(cudaMemcpy(c, counters, sizeof(c), cudaMemcpyDeviceToHost), "cudaMemcpy");
    appended = 0;
    for (uint32_t s = 0; s < kStripes; ++s) appended += c[s];
  }
  state.counters["appended"] = double(appended);
  state.counters["appends_per_s"] = benchmark::Counter(double(appended), benchmark::Counter::kIsIterationInvariantRate);
  cudaEventDestroy(start);
  cudaEventDestroy(stop);
  cudaFree(counters);
  cudaFree(out);
}

void cases(benchmark::internal::Benchmark* b) {
  b->ArgNames({"n", "lanes", "mode"});
  for (int mode : {kClaimOne, kPerLane, kStriped, kCountOne, kPlainStore})
    for (int lanes : {32, 8, 2}) b->Args({1 << 21, lanes, mode});
}

BENCHMARK(append)->Apply(cases)->UseManualTime()->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
