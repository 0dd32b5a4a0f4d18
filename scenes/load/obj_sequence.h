#pragma once
// A directory of OBJ files, one per frame in natural name order (f2.obj before f10.obj;
// io/input_files.h), read by io/obj_reader.h. Frame 0 fixes the topology; every later
// frame must match it (the same faces, vertex count) and be finite, which is checked for all
// frames when the directory is opened.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

std::unique_ptr<FrameSource> open_mesh_sequence(const std::filesystem::path& dir);

// Writes a scene's frames as such a directory (frame_0000.obj, ...; created if needed,
// frames of the same names overwritten) that reads back to the same triangles in the same
// order and the same positions. Throws naming the file on a write failure.
void write_obj_sequence(const FrameSource& source, const std::filesystem::path& out_dir);

// Reads one mesh file: all its meshes' triangles in file order, no vertex merging, no
// dropping of degenerate faces; polygons are triangulated (their count is returned, so the
// caller can say so). Throws naming the file (and `frame`, when >= 0) on any failure.
size_t read_mesh_file(const std::filesystem::path& file, Topology& topology,
                      std::vector<vec3d>& positions, int64_t frame = -1);

}  // namespace cdb
