#pragma once
// A box stream: a directory of per-frame primitive boxes, as simulators export them instead
// of meshes. One file per frame in natural name order (io/natural_order.h), all of one format:
//   .boxes    little-endian float32 min.x min.y min.z max.x max.y max.z per box (24 bytes),
//             no header: the box count is the file size / 24;
//   .boxes64  the same in float64 (48 bytes per box);
//   .npy      NumPy format 1.0-3.0, dtype '<f4' or '<f8', shape (N, 6) or (N, 2, 3), C order.
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
#include <vector>

#include "geometry/frame_source.h"

namespace cdb {

// Whether the file's extension is one of a box frame's (.boxes, .boxes64, .npy; any case).
bool is_box_frame_file(const std::filesystem::path& file);

// One frame's boxes, 6 coordinates each in the order above, widened to double; `frame`
// is only for messages. Throws cdb::Error naming the file, frame and box on bad data.
void read_box_frame(const std::filesystem::path& file, uint32_t frame, std::vector<double>& boxes);

std::unique_ptr<FrameSource> open_box_stream(const std::filesystem::path& dir);

}  // namespace cdb
