#pragma once
// Per-vertex keyframe files (Quake II MD2, also MD3 and other formats assimp reads one
// keyframe at a time): assimp imports a single keyframe per import, chosen by
// AI_CONFIG_IMPORT_GLOBAL_KEYFRAME, so frame k is a fresh import of keyframe first + k (with
// subframes s: keyframe first + k / s, blended linearly towards the next one by (k mod s) / s,
// as Quake II plays them). The topology is taken once; every keyframe must have the same
// meshes, faces and vertices.
#include <cstdint>
#include <filesystem>
#include <memory>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

struct KeyframeOptions {
  std::filesystem::path file;
  uint32_t first = 0;      // keyframe of frame 0
  uint32_t frames = 0;     // 0: up to the file's last keyframe (the count read from its header)
  uint32_t subframes = 1;  // frames per keyframe interval: between keyframes, linear blends
};

// The number of keyframes an MD2 or MD3 file's header declares; 0 for other formats, whose
// count assimp does not report. Throws naming the file when the header is cut short.
uint32_t keyframes_in_header(const std::filesystem::path& file);

// Imports every keyframe once to check that the topology stays fixed and to weld vertices
// that are the same in every keyframe. Throws cdb::Error naming the file and keyframe.
std::unique_ptr<FrameSource> open_keyframe_mesh(const KeyframeOptions& options);

}  // namespace cdb
