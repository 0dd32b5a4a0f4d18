#pragma once
// Files a generator builds on: a scanned mesh (dragon) or an animated character (flamenco).
// The scenes library reads no file format itself; the scene loader (scenes/load/scene.cpp) opens
// them with the loaders the descriptors use, so a missing file names the Debian package
// that ships it, archive members come from the scene cache, and the generators stay free of
// assimp.
#include <functional>
#include <string>
#include <vector>

#include "scenes/generators/dvec.h"
#include "cdbench/geometry/frame_source.h"

namespace cdb::scene {

struct InputMesh {
  std::vector<dvec3> positions;  // welded: one index per position
  std::vector<Tri> faces;
};

struct InputAnimation {
  Topology topology;   // the character's triangles, one object per mesh
  double seconds = 0;  // the clip's length
  // Positions at `seconds` into the clip.
  std::function<void(double seconds, std::vector<vec3f>& out)> at;
};

class SceneInputs {
 public:
  virtual ~SceneInputs() = default;
  // `file`, or with `member` not empty that member of the gzip-compressed tar `file`.
  virtual InputMesh mesh(const std::string& file, const std::string& member) const = 0;
  // The first clip of an animated file (any format assimp reads).
  virtual InputAnimation animation(const std::string& file) const = 0;
};

}  // namespace cdb::scene
