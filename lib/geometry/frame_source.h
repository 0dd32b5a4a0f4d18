#pragma once
// A scene's triangles over time: fixed topology, positions per frame, produced on demand
// (procedural generators compute them, loaders read them), so a 10M-triangle scene of
// many frames never sits in memory all at once.
#include <cstdint>
#include <string>
#include <vector>

#include "core/vec.h"
#include "geometry/mesh.h"

namespace cdb {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const Topology& topology() const = 0;
  virtual uint32_t num_frames() const = 0;
  // Positions of frame k. Throws cdb::Error naming the file, frame and vertex on bad data
  // (NaN/Inf, wrong vertex count).
  virtual void frame(uint32_t k, std::vector<vec3f>& out) const = 0;
  virtual std::string describe() const = 0;
};

// Rejects NaN/Inf positions and a vertex count that differs from the topology's.
void check_frame(const std::vector<vec3f>& positions, const Topology& topology,
                 const std::string& where, uint32_t frame);

}  // namespace cdb
