#pragma once
// A plain reader for Wavefront OBJ frames: `v` and `f` lines, everything else ignored.
// Coordinates go through strtod, which rounds correctly, and stay in double (the oracle
// judges the file's geometry, --box-precision fp64 keeps it), so a frame written with
// enough digits (io/obj_writer.h) reads back to the same numbers; assimp's OBJ number
// parser does not (it accumulates in float and was found 2 ulps off on exponent forms
// such as -2.13448675e-05). Vertices are kept as the file lists them (no per-corner duplication),
// faces in file order; polygons become fans (0, k, k+1) and are counted for the caller.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "cdbench/core/vec.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

// Returns the number of polygon faces (more than 3 corners) that were triangulated. Throws
// naming the file, the frame (when `frame` >= 0) and the line on a malformed vertex (a
// coordinate that is not a number, trailing text that is not), a NaN or Inf coordinate,
// one beyond float range, a face with fewer than 3 corners, a malformed corner or an index
// out of range (negative indices count back from the last vertex, as OBJ defines).
size_t read_obj_file(const std::filesystem::path& file, Topology& topology, std::vector<vec3d>& positions,
                     int64_t frame = -1);

}  // namespace cdb
