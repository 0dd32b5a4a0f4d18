#pragma once
// One animated file that assimp reads (glTF/GLB, FBX, COLLADA, X, ...) as a scene sampled
// at a frame rate: node animation channels, node hierarchy and skeletal skinning are
// evaluated on the CPU for each frame from the bind pose read once.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>

#include "geometry/frame_source.h"

namespace cdb {

struct AnimationOptions {
  std::filesystem::path file;
  double fps = 30;
  uint32_t frames = 0;    // 0: from `start` to the end of the clip
  double start = 0;       // seconds into the clip of frame 0
  uint32_t clip = 0;      // index into the file's animations
  std::string clip_name;  // when set, the clip of this name instead of `clip`
};

// One object per mesh instance (a node referencing a mesh), in node depth-first order,
// named after the mesh, else its node. Throws cdb::Error naming the file (and the clip,
// mesh, bone or frame) on any failure.
std::unique_ptr<FrameSource> open_animated_mesh(const AnimationOptions& options);

}  // namespace cdb
