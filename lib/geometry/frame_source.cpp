#include "cdbench/geometry/frame_source.h"

#include <cmath>

#include "cdbench/core/error.h"

namespace cdb {

void FrameSource::frame(uint32_t k, std::vector<vec3f>& out) const {
  std::vector<vec3d> p;
  positions(k, p);
  round_to_float(p, out);
}

void check_frame(const std::vector<vec3d>& positions, const Topology& topology,
                 const std::string& where, uint32_t frame) {
  if (positions.size() != topology.num_vertices)
    fail(where + ": frame " + std::to_string(frame) + " has " + std::to_string(positions.size()) +
         " vertices, frame 0 has " + std::to_string(topology.num_vertices) +
         " (topology must stay fixed)");
  for (size_t v = 0; v < positions.size(); ++v) {
    const vec3d p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(where + ": frame " + std::to_string(frame) + ", vertex " + std::to_string(v) +
           ": non-finite position (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
           std::to_string(p.z) + ")");
  }
}

void round_to_float(const std::vector<vec3d>& in, std::vector<vec3f>& out) {
  out.resize(in.size());
  for (size_t v = 0; v < in.size(); ++v)
    out[v] = {static_cast<float>(in[v].x), static_cast<float>(in[v].y), static_cast<float>(in[v].z)};
}

void widen_to_double(const std::vector<vec3f>& in, std::vector<vec3d>& out) {
  out.resize(in.size());
  for (size_t v = 0; v < in.size(); ++v) out[v] = {in[v].x, in[v].y, in[v].z};
}

}  // namespace cdb
