#pragma once
// The public API tests' scene (test_api.cpp, test_api_cuda.cpp): a side x side cloth waving
// and folding onto itself, as the API takes it.
#include <cmath>
#include <cstdint>
#include <vector>

#include "cdbench/cdbench.h"

namespace cdb::test {

inline cdbench::Topology api_cloth(uint32_t side) {
  std::vector<cdbench::Triangle> t;
  for (uint32_t i = 0; i < side; ++i)
    for (uint32_t j = 0; j < side; ++j) {
      const uint32_t v = i * (side + 1) + j;
      t.push_back({v, v + 1, v + side + 1});
      t.push_back({v + 1, v + side + 2, v + side + 1});
    }
  return cdbench::Topology::mesh(t, (side + 1) * (side + 1));
}

// x, y, z per vertex of api_cloth(side) at `frame`.
inline std::vector<float> api_cloth_waving(uint32_t side, int frame) {
  std::vector<float> xyz;
  const float t = 0.3f * float(frame);
  for (uint32_t i = 0; i <= side; ++i)
    for (uint32_t j = 0; j <= side; ++j) {
      const float x = float(j) / float(side), y = float(i) / float(side);
      xyz.insert(xyz.end(), {x + 0.08f * std::sin(6.0f * y + t), y, 0.1f * std::sin(9.0f * x - 2.0f * t)});
    }
  return xyz;
}

}  // namespace cdb::test
