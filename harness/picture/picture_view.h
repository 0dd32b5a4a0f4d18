#pragma once
// Where a picture looks from: along an axis (x, y, z: from that axis's positive side) or
// from the (1, 1, 1) corner (iso). The scenes' up is +y (gravity pulls along -y), so every
// view but y keeps +y up on the picture; y looks down from above with -z up.
#include <string>

#include "cdbench/core/vec.h"

namespace cdb {

enum class PictureView { x, y, z, iso };

// Throws cdb::Error naming the known views.
PictureView parse_picture_view(const std::string& name);

// An orthonormal, right-handed frame: right x up = toward_viewer.
struct ViewBasis {
  vec3d right, up, toward_viewer;
};

ViewBasis view_basis(PictureView view);

}  // namespace cdb
