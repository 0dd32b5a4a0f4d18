#pragma once
// Exact CPU oracle for scenes too large for O(N^2): sort boxes by their lower x bound,
// then sweep. Plain serial code on purpose: it is the independent reference the GPU
// pipelines are checked against.
#include <vector>

#include "cdbench/core/pair.h"
#include "cdbench/core/vec.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

// skip_adjacent: leave out pairs of triangles that share a vertex (co-vertex filtering).
// A topology with declared queries keeps only the pairs they ask for. The double overload
// judges the scene's own geometry (what --check and verify compare against); the float one
// the floats a pipeline ran on.
std::vector<PrimPair> sweep_oracle_pairs(const Topology& topology,
                                         const std::vector<vec3f>& vertices,
                                         bool skip_adjacent = false);
std::vector<PrimPair> sweep_oracle_pairs(const Topology& topology,
                                         const std::vector<vec3d>& vertices,
                                         bool skip_adjacent = false);

}  // namespace cdb
