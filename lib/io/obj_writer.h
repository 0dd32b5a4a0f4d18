#pragma once
// Writes a scene's frames as a directory of OBJ files (frame_0000.obj, ...) that
// open_mesh_sequence reads back: same triangles in the same order, same float positions.
#include <filesystem>

#include "geometry/frame_source.h"

namespace cdb {

// Creates out_dir if needed; overwrites frames of the same names. Throws naming the file
// on a write failure.
void write_obj_sequence(const FrameSource& source, const std::filesystem::path& out_dir);

}  // namespace cdb
