#pragma once
// The `cloth-wave` scene of `cdbench run --scene cloth-wave` (scenes/cloth-wave.json: the
// generator of scenes/generators/generators.cpp at res 128, 60 frames), rebuilt on the public
// API alone: a res x res vertex cloth with a wave travelling across it while its far edge rolls
// up over the sheet. The same triangles in the same order and, for the same frame count, the
// same positions rounded to float as the CLI runs them (fp32 boxes), so pair counts match.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "cdbench/cdbench.h"

class ClothWave {
 public:
  // `frames`: the length of the motion (the roll advances from frame 0 to frames - 1).
  ClothWave(uint32_t res, uint32_t frames) : res_(res), frames_(frames) {}

  uint32_t num_vertices() const { return res_ * res_; }

  cdbench::Topology topology() const {
    std::vector<cdbench::Triangle> triangles;
    triangles.reserve(2 * size_t(res_ - 1) * (res_ - 1));
    for (uint32_t j = 0; j + 1 < res_; ++j)
      for (uint32_t i = 0; i + 1 < res_; ++i) {
        const uint32_t a = j * res_ + i, b = a + 1, c = a + res_, d = c + 1;
        triangles.push_back({a, b, d});
        triangles.push_back({a, d, c});
      }
    return cdbench::Topology::mesh(std::move(triangles), num_vertices());
  }

  // Frame k's x, y, z per vertex, computed in double and rounded to float; `out` is resized
  // once and reused.
  void positions(uint32_t k, std::vector<float>& out) const {
    out.resize(3 * size_t(num_vertices()));
    const double t = frames_ > 1 ? double(k) / (frames_ - 1) : 0.0;
    const double roll_start = 0.85 - 0.45 * t;  // the roll eats into the sheet over time
    const double radius = 0.06;
    for (uint32_t j = 0; j < res_; ++j)
      for (uint32_t i = 0; i < res_; ++i) {
        const double s = double(i) / (res_ - 1), z = double(j) / (res_ - 1);
        double x = s, y = 0.03 * std::sin(12.0 * s - 8.0 * t + 3.0 * z);
        if (s > roll_start) {
          const double theta = (s - roll_start) / radius;
          const double r = radius * std::max(0.2, 1.0 - 0.04 * theta);
          x = roll_start + r * std::sin(theta);
          y += r * (1.0 - std::cos(theta));
        }
        float* p = &out[3 * (size_t(j) * res_ + i)];
        p[0] = static_cast<float>(x);
        p[1] = static_cast<float>(y);
        p[2] = static_cast<float>(z);
      }
  }

 private:
  uint32_t res_, frames_;
};
