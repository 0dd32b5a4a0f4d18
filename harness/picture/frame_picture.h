#pragma once
// A picture of one frame of a scene: its triangles drawn orthographically from a view,
// flat-shaded by each triangle's normal (ambient plus Lambert, both faces lit alike), those
// in at least one pair of the frame's pair set in a contrasting red-orange, the others in
// grey-blue, tinted per object when the scene has several. For a user to see that frames
// loaded as meant and where the contacts are.
#include <cstdint>
#include <vector>

#include "cdbench/core/pair.h"
#include "cdbench/core/vec.h"
#include "cdbench/geometry/mesh.h"
#include "harness/picture/picture_view.h"
#include "harness/picture/rgb_image.h"

namespace cdb {

// The colour of a triangle in a pair, lit head-on; shading only darkens it.
inline constexpr Rgb kContactColour{235, 85, 30};
inline constexpr Rgb kBackgroundColour{255, 255, 255};

// Per face, whether it is in one of the pairs (face indices below num_faces).
std::vector<uint8_t> faces_in_pairs(const std::vector<PrimPair>& pairs, size_t num_faces);

// A size x size picture of the triangles of `topology` at `positions`, the whole scene
// fitted into it; `marked` (per face) are drawn in kContactColour. A marked triangle too
// small to cover a pixel centre still gets the pixel of its centroid where nothing hides it.
RgbImage frame_picture(const Topology& topology, const std::vector<vec3d>& positions,
                       const std::vector<uint8_t>& marked, PictureView view, uint32_t size);

}  // namespace cdb
