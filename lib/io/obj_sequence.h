#pragma once
// A directory of mesh files, one per frame in name order (frame_0000.obj, ...), read with
// assimp. Frame 0 fixes the topology; every later frame must match it.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "geometry/frame_source.h"

namespace cdb {

std::unique_ptr<FrameSource> open_mesh_sequence(const std::filesystem::path& dir);

// Reads one mesh file: all its meshes' triangles in file order, no vertex merging, no
// dropping of degenerate faces; polygons are triangulated (their count is returned, so the
// caller can say so). Throws naming the file on any failure.
size_t read_mesh_file(const std::filesystem::path& file, Topology& topology,
                      std::vector<vec3f>& positions);

}  // namespace cdb
