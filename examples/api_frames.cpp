// The API's cost per frame: the cloth of `cdbench run --scene cloth-wave` (128 x 128 vertices,
// cloth_wave.h) run for N frames through cdbench::BroadPhase, each call timed on the host
// (steady_clock around run() or run_device(), its one synchronization included) beside the
// frame time the API reports; their difference is what the API adds to the frame. On "cuda"
// the positions come from device memory this program owns (device_positions.h), written on its
// own stream before each timed call. Also: the pairs against the oracle on a few frames, and
// the heap allocations of each frame's calls: none once sizes settle, that is on every frame
// where no buffer grew (the executor's, FrameStats::buffer_allocations, and on "cpu" the pair
// vector pairs() fills, which grows when the count passes every earlier one). The warm-up
// covers what a pipeline allocates once on its first use (on "cpu", the first refit's block
// memory at frame 1).
//   api_frames [pipeline] [executor] [frames] [warmup]     (defaults: c cpu 60 5)
// Exit status 0 when the checked frames equal the oracle and no measured frame allocated
// without a buffer growing, 1 otherwise, 2 on an error.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "allocation_count.h"
#include "cdbench/cdbench.h"
#include "cloth_wave.h"
#include "device_positions.h"

namespace {

struct Summary {
  double mean = 0, median = 0, p95 = 0;
};

// Of the measured frames (warm-up left out); p95 by nearest rank.
Summary summarize(std::vector<double> values) {
  Summary s;
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  for (double v : values) s.mean += v;
  s.mean /= double(values.size());
  const size_t n = values.size();
  s.median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  s.p95 = values[std::min(n - 1, size_t((95 * n + 99) / 100) - 1)];
  return s;
}

bool same_pairs(const std::vector<cdbench::Pair>& a, const std::vector<cdbench::Pair>& b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](cdbench::Pair x, cdbench::Pair y) { return x.a == y.a && x.b == y.b; });
}

// A few frames spread over the run, the first and the last among them.
bool checked_frame(int f, int frames) { return f == frames - 1 || f % std::max(1, frames / 4) == 0; }

}  // namespace

int main(int argc, char** argv) {
  const std::string pipeline = argc > 1 ? argv[1] : "c", executor = argc > 2 ? argv[2] : "cpu";
  const int frames = argc > 3 ? std::atoi(argv[3]) : 60;
  const int warmup = argc > 4 ? std::atoi(argv[4]) : 5;
  if (frames < 1 || warmup < 0 || warmup >= frames) {
    std::fprintf(stderr, "api_frames: need frames >= 1 and 0 <= warmup < frames (got %d, %d)\n", frames, warmup);
    return 2;
  }
  const ClothWave cloth(128, uint32_t(frames));
  const cdbench::Topology topology = cloth.topology();
  const uint32_t vertices = cloth.num_vertices();
  try {
    cdbench::BroadPhase broad_phase({.pipeline = pipeline, .executor = executor}, topology);
    const bool on_device = executor == "cuda";
    std::unique_ptr<DevicePositions> device;
    if (on_device) device = std::make_unique<DevicePositions>(vertices);
    std::printf("api_frames: pipeline %s on %s, cloth-wave 128x128 (%zu triangles), %d frames, first %d warm-up\n",
                pipeline.c_str(), executor.c_str(), topology.triangles.size(), frames, warmup);

    std::vector<float> xyz;
    std::vector<cdbench::Pair> pairs;
    std::vector<double> wall_ms, api_ms, overhead_ms;
    wall_ms.reserve(size_t(frames));
    api_ms.reserve(size_t(frames));
    overhead_ms.reserve(size_t(frames));
    uint64_t pairs_min = UINT64_MAX, pairs_max = 0, settled_allocations = 0;
    int mismatches = 0, growing_frames = 0, allocating_frames = 0, checked = 0;
    for (int f = 0; f < frames; ++f) {
      cloth.positions(uint32_t(f), xyz);
      if (device) device->write(xyz.data());
      // The calls a simulator makes each frame: the frame, then its pairs where they lie.
      const size_t pairs_capacity = pairs.capacity();
      const uint64_t allocations_before = heap_allocations();
      const auto start = std::chrono::steady_clock::now();
      const cdbench::FrameStats& stats = on_device
                                             ? broad_phase.run_device(device->data(), vertices, device->stream())
                                             : broad_phase.run(xyz.data(), vertices);
      const auto end = std::chrono::steady_clock::now();
      size_t pair_count = 0;
      if (on_device) {
        pair_count = broad_phase.device_pairs().count;
      } else {
        broad_phase.pairs(pairs);
        pair_count = pairs.size();
      }
      const uint64_t allocations = heap_allocations() - allocations_before;
      const uint32_t grown = stats.buffer_allocations + (pairs.capacity() != pairs_capacity ? 1 : 0);

      const double wall = std::chrono::duration<double, std::milli>(end - start).count();
      const bool measured = f >= warmup;
      if (measured) {
        wall_ms.push_back(wall);
        api_ms.push_back(stats.time_ms);
        overhead_ms.push_back(wall - stats.time_ms);
        pairs_min = std::min(pairs_min, stats.pairs);
        pairs_max = std::max(pairs_max, stats.pairs);
        if (grown) {
          ++growing_frames;
        } else if (allocations) {
          settled_allocations += allocations;
          ++allocating_frames;
        }
      }
      std::string verdict;
      if (pair_count != stats.pairs) {
        verdict = "  MISMATCH (pairs read " + std::to_string(pair_count) + ")";
        ++mismatches;
      }
      if (checked_frame(f, frames)) {
        broad_phase.pairs(pairs);
        const bool same = same_pairs(pairs, cdbench::oracle_pairs(topology, xyz.data(), vertices));
        verdict += same ? "  = oracle" : "  MISMATCH";
        ++checked;
        if (!same) ++mismatches;
      }
      std::printf("frame %3d  %-16s wall %8.4f ms  api %8.4f ms  overhead %8.4f ms  pairs %7llu  syncs %u  "
                  "allocations %llu  grown %u%s%s\n",
                  f, stats.op.c_str(), wall, stats.time_ms, wall - stats.time_ms, (unsigned long long)stats.pairs,
                  stats.host_syncs, (unsigned long long)allocations, grown,
                  measured ? "" : "  (warm-up)", verdict.c_str());
    }
    const Summary wall = summarize(wall_ms), api = summarize(api_ms), overhead = summarize(overhead_ms);
    const size_t n = wall_ms.size();
    std::printf("summary: %s on %s, %zu frames measured (first %d left out)\n", pipeline.c_str(), executor.c_str(),
                n, warmup);
    std::printf("  wall      mean %8.4f  median %8.4f  p95 %8.4f ms\n", wall.mean, wall.median, wall.p95);
    std::printf("  api       mean %8.4f  median %8.4f  p95 %8.4f ms\n", api.mean, api.median, api.p95);
    std::printf("  overhead  mean %8.4f  median %8.4f  p95 %8.4f ms\n", overhead.mean, overhead.median, overhead.p95);
    std::printf("  pairs     min %llu  max %llu\n", (unsigned long long)pairs_min, (unsigned long long)pairs_max);
    std::printf("  measured frames whose buffers grew: %d; heap allocations in the others: %llu (%d frames)\n",
                growing_frames, (unsigned long long)settled_allocations, allocating_frames);
    std::printf("  oracle: %d frames checked, %s\n", checked, mismatches ? "MISMATCH" : "every one equal");
    const bool ok = mismatches == 0 && settled_allocations == 0;
    std::printf("api_frames %s on %s: %s\n", pipeline.c_str(), executor.c_str(),
                ok ? "PASS" : mismatches ? "FAIL (pairs differ)" : "FAIL (frames allocate)");
    return ok ? 0 : 1;
  } catch (const cdbench::Error& e) {
    std::fprintf(stderr, "api_frames: %s\n", e.what());
    return 2;
  }
}
