#include "cdbench/geometry/float_spacing.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "cdbench/geometry/position_rounding.h"

namespace cdb {

FloatSpacing float_spacing(const Topology& topology, const std::vector<vec3d>& positions, vec3d origin) {
  FloatSpacing s;
  for (const vec3d& p : positions)
    s.largest = std::max({s.largest, std::fabs(p.x - origin.x), std::fabs(p.y - origin.y), std::fabs(p.z - origin.z)});
  const float f = static_cast<float>(std::min(s.largest, double(std::numeric_limits<float>::max())));
  s.spacing = double(std::nextafter(f, std::numeric_limits<float>::infinity())) - double(f);
  std::vector<double> edges;
  edges.reserve(3 * topology.faces.size());
  const auto length = [&](uint32_t a, uint32_t b) {
    const vec3d p = positions[a], q = positions[b];
    return std::sqrt((p.x - q.x) * (p.x - q.x) + (p.y - q.y) * (p.y - q.y) + (p.z - q.z) * (p.z - q.z));
  };
  for (const Tri& t : topology.faces) {
    edges.push_back(length(t.v0, t.v1));
    edges.push_back(length(t.v1, t.v2));
    edges.push_back(length(t.v2, t.v0));
  }
  if (!edges.empty()) {
    auto mid = edges.begin() + std::ptrdiff_t(edges.size() / 2);
    std::nth_element(edges.begin(), mid, edges.end());
    s.median_edge = *mid;
  }
  return s;
}

std::string float_spacing_warning(const FloatSpacing& s, bool rebased) {
  if (!s.too_coarse()) return {};
  char text[400];
  std::snprintf(text, sizeof text,
                "float spacing %.3g at the largest coordinate %.6g exceeds 1/%.0f of the median edge %.3g: "
                "float boxes blur the geometry (extra pairs)%s",
                s.spacing, s.largest, 1.0 / kFeatureFraction, s.median_edge,
                rebased ? "; the scene is too wide for its features even from its centre"
                        : "; --box-precision fp64 rebases the scene on its centre first");
  return text;
}

std::string float_spacing_warning(const FrameSource& source, uint32_t k, bool rebase) {
  std::vector<vec3d> p;
  source.positions(k, p);
  const vec3d origin = rebase ? bounds_centre(p) : vec3d{0, 0, 0};
  return float_spacing_warning(float_spacing(source.topology(), p, origin), rebase);
}

}  // namespace cdb
