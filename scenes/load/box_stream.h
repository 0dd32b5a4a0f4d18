#pragma once
// A box stream: a directory of per-frame primitive boxes, as simulators export them instead
// of meshes, one file per frame in natural name order, all .boxes (float32 min.xyz max.xyz
// per box), .boxes64 (float64) or .npy (docs/usage.md "Your own data" has the formats).
// Box i becomes two vertices, 2i its min corner and 2i + 1 its max corner, and the degenerate
// face (2i, 2i+1, 2i+1): the box of that triangle (core/aabb.h triangle_box, min and max of
// its corners) is the input box exactly, so every pipeline, the oracle, margins, swept boxes
// and fp64 read a box as a primitive unchanged. Topology::box_faces counts such faces: they
// have no triangle for the contact checks of `run --check`.
// Every frame is read and checked when the directory is opened: the same box count in every
// frame, a file size that fits the format, finite coordinates, min <= max on every axis, no
// empty frame; each error names the file, the frame and the box.
#include <filesystem>
#include <memory>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

// Whether the file's extension is one of a box frame's (.boxes, .boxes64, .npy; any case).
bool is_box_frame_file(const std::filesystem::path& file);

std::unique_ptr<FrameSource> open_box_stream(const std::filesystem::path& dir);

}  // namespace cdb
