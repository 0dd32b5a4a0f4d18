#pragma once
// A scene's triangles over time: fixed topology, positions per frame, produced on demand
// (procedural generators compute them, loaders read them), so a 10M-triangle scene of
// many frames never sits in memory all at once.
#include <cstdint>
#include <string>
#include <vector>

#include "cdbench/core/vec.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual const Topology& topology() const = 0;
  virtual uint32_t num_frames() const = 0;
  // Positions of frame k in double, as the source holds them (an OBJ's decimal digits, a
  // simulation's state, a placement's offset): the geometry the oracle and --check judge
  // against. Throws cdb::Error naming the file, frame and vertex on bad data (NaN/Inf,
  // wrong vertex count).
  virtual void positions(uint32_t k, std::vector<vec3d>& out) const = 0;
  virtual std::string describe() const = 0;
  // Frame k rounded to the nearest floats: what a float pipeline reads without a rebase.
  void frame(uint32_t k, std::vector<vec3f>& out) const;
};

// Rejects NaN/Inf positions and a vertex count that differs from the topology's.
void check_frame(const std::vector<vec3d>& positions, const Topology& topology,
                 const std::string& where, uint32_t frame);

// Each coordinate rounded to the nearest float (overflow: +-inf, rejected by check_frame).
void round_to_float(const std::vector<vec3d>& in, std::vector<vec3f>& out);
// Floats widened exactly to double.
void widen_to_double(const std::vector<vec3f>& in, std::vector<vec3d>& out);

}  // namespace cdb
