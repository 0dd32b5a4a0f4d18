// A simulator's loop: a cloth of n x n quads (two triangles each) waving, the broad phase run
// each frame, its pairs checked against the exact oracle. Exit status 0 when every frame
// matches, 1 on a mismatch, 2 on an error.
//   cloth_loop [pipeline] [executor] [frames]     (defaults: c cpu 20)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cdbench/cdbench.h"

int main(int argc, char** argv) {
  const std::string pipeline = argc > 1 ? argv[1] : "c", executor = argc > 2 ? argv[2] : "cpu";
  const int frames = argc > 3 ? std::atoi(argv[3]) : 20;
  constexpr uint32_t n = 24;  // quads per side
  std::vector<cdbench::Triangle> triangles;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = 0; j < n; ++j) {
      const uint32_t v = i * (n + 1) + j;
      triangles.push_back({v, v + 1, v + n + 1});
      triangles.push_back({v + 1, v + n + 2, v + n + 1});
    }
  const uint32_t vertices = (n + 1) * (n + 1);
  const cdbench::Topology topology = cdbench::Topology::mesh(triangles, vertices);
  try {
    cdbench::BroadPhase broad_phase({.pipeline = pipeline, .executor = executor, .skip_adjacent = true}, topology);
    std::vector<float> xyz(3 * vertices);
    std::vector<cdbench::Pair> pairs;
    int mismatches = 0;
    for (int f = 0; f < frames; ++f) {
      // A wave crossing the cloth, steep enough to fold it onto itself, so pairs change.
      const float t = 0.15f * float(f);
      for (uint32_t i = 0; i <= n; ++i)
        for (uint32_t j = 0; j <= n; ++j) {
          const float x = float(j) / n, y = float(i) / n;
          float* p = &xyz[3 * (i * (n + 1) + j)];
          p[0] = x + 0.08f * std::sin(6.0f * y + t);
          p[1] = y;
          p[2] = 0.1f * std::sin(9.0f * x - 2.0f * t);
        }
      const cdbench::FrameStats& stats = broad_phase.run(xyz.data(), vertices);
      broad_phase.pairs(pairs);
      const std::vector<cdbench::Pair> expected = cdbench::oracle_pairs(topology, xyz.data(), vertices, true);
      const bool same = pairs.size() == expected.size() &&
                        std::equal(pairs.begin(), pairs.end(), expected.begin(),
                                   [](cdbench::Pair a, cdbench::Pair b) { return a.a == b.a && a.b == b.b; });
      std::printf("frame %2d  %-16s %8.3f ms  pairs %6llu  %s\n", f, stats.op.c_str(), stats.time_ms,
                  (unsigned long long)stats.pairs, same ? "= oracle" : "MISMATCH");
      if (!same) ++mismatches;
    }
    std::printf("%s on %s: %s\n", pipeline.c_str(), executor.c_str(),
                mismatches ? "MISMATCH" : "every frame equals the oracle");
    return mismatches ? 1 : 0;
  } catch (const cdbench::Error& e) {
    std::fprintf(stderr, "cloth_loop: %s\n", e.what());
    return 2;
  }
}
