#pragma once
// Scenes put together from parts (a generated cloth, an animated character, a rigid scan
// moving, ...) and crowds of one animated character.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cdbench/geometry/frame_source.h"
#include "scenes/load/animated_mesh.h"

namespace cdb {

struct ScenePart {
  std::string name;
  std::unique_ptr<FrameSource> source;
  bool rigid = false;
};

// The parts concatenated in order (faces and vertices numbered part after part), one object
// per part covering its faces, over the first `frames` frames of every part (each must have
// that many).
std::unique_ptr<FrameSource> compose_parts(std::vector<ScenePart> parts, uint32_t frames);

struct CrowdOptions {
  AnimationOptions animation;  // the character: file, clip, fps, start (frames: see below)
  uint32_t count = 16;
  uint32_t columns = 0;  // 0: ceil(sqrt(count))
  // Grid step as a fraction of the character's frame-0 footprint along each ground axis:
  // below 1 neighbours overlap.
  double spacing = 0.8;
  // Instance i plays the clip from (i * phase_step) mod clip length; below 0: the golden
  // ratio's fraction of the clip, which keeps every phase apart.
  double phase_step = -1;
  int up_axis = 1;          // 0 x, 1 y, 2 z; the grid spans the other two
  uint32_t frames = 0;      // 0: one clip length at fps
  bool instance_objects = false;  // one object per instance (name#i), else one for the crowd
  std::string name = "crowd";
};

// `count` instances of the clip on a grid, each looping the clip from its own phase.
std::unique_ptr<FrameSource> open_crowd(const CrowdOptions& options);

}  // namespace cdb
