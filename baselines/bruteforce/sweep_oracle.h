#pragma once
// Exact CPU oracle for scenes too large for O(N^2): sort boxes by their lower x bound,
// then sweep. Plain serial code on purpose: it is the independent reference the GPU
// pipelines are checked against.
#include <vector>

#include "core/pair.h"
#include "core/vec.h"
#include "geometry/mesh.h"

namespace cdb {

// skip_adjacent: leave out pairs of triangles that share a vertex (co-vertex filtering).
// A topology with declared queries keeps only the pairs they ask for.
std::vector<PrimPair> sweep_oracle_pairs(const Topology& topology,
                                         const std::vector<vec3f>& vertices,
                                         bool skip_adjacent = false);

}  // namespace cdb
