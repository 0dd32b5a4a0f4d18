#include "harness/picture/picture_view.h"

#include <cmath>

#include "cdbench/core/error.h"

namespace cdb {

PictureView parse_picture_view(const std::string& name) {
  if (name == "x") return PictureView::x;
  if (name == "y") return PictureView::y;
  if (name == "z") return PictureView::z;
  if (name == "iso") return PictureView::iso;
  fail("unknown view '" + name + "' (known: x, y, z, iso)");
}

ViewBasis view_basis(PictureView view) {
  switch (view) {
    case PictureView::x: return {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}};
    case PictureView::y: return {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}};
    case PictureView::z: return {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    case PictureView::iso: break;
  }
  const double t = 1 / std::sqrt(3.0), r = 1 / std::sqrt(2.0), u = 1 / std::sqrt(6.0);
  // toward (1,1,1)/sqrt3; up: +y with its part along toward taken out; right = up x toward.
  return {{r, 0, -r}, {-u, 2 * u, -u}, {t, t, t}};
}

}  // namespace cdb
