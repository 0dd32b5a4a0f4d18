#pragma once
// One animated file that assimp reads (glTF/GLB, FBX, COLLADA, X, ...) as a scene sampled
// at a frame rate: node animation channels, node hierarchy and skeletal skinning are
// evaluated on the CPU for each frame from the bind pose read once.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cdbench/geometry/frame_source.h"

namespace cdb {

struct AnimationOptions {
  std::filesystem::path file;
  double fps = 30;
  uint32_t frames = 0;    // 0: from `start` to the end of the clip
  double start = 0;       // seconds into the clip of frame 0
  uint32_t clip = 0;      // index into the file's animations
  std::string clip_name;  // when set, the clip of this name instead of `clip`
};

// An animated file's frames, which can also be sampled at any time of its clip (crowds
// place instances at different phases of one clip).
class AnimatedClip : public FrameSource {
 public:
  // Positions at `seconds` into the clip; `fps` and `start` play no part.
  virtual void positions_at(double seconds, std::vector<vec3f>& out) const = 0;
  virtual double clip_seconds() const = 0;
};

// One object per mesh instance (a node referencing a mesh), in node depth-first order,
// named after the mesh, else its node. Throws cdb::Error naming the file (and the clip,
// mesh, bone or frame) on any failure.
std::unique_ptr<AnimatedClip> open_animated_clip(const AnimationOptions& options);

}  // namespace cdb
