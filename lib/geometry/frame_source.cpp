#include "geometry/frame_source.h"

#include <cmath>

#include "core/error.h"

namespace cdb {

void check_frame(const std::vector<vec3f>& positions, const Topology& topology,
                 const std::string& where, uint32_t frame) {
  if (positions.size() != topology.num_vertices)
    fail(where + ": frame " + std::to_string(frame) + " has " + std::to_string(positions.size()) +
         " vertices, frame 0 has " + std::to_string(topology.num_vertices) +
         " (topology must stay fixed)");
  for (size_t v = 0; v < positions.size(); ++v) {
    const vec3f p = positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail(where + ": frame " + std::to_string(frame) + ", vertex " + std::to_string(v) +
           ": non-finite position (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " +
           std::to_string(p.z) + ")");
  }
}

}  // namespace cdb
