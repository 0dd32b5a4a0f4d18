#include "cdbench/geometry/margin_range.h"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <string>

#include "cdbench/core/error.h"
#include "cdbench/core/outward_rounding.h"

namespace cdb {

void check_margin_in_float_range(const std::vector<vec3f>& vertices, float margin, bool widen) {
  if (!(margin > 0.0f)) return;
  const float inf = std::numeric_limits<float>::infinity();
  for (size_t v = 0; v < vertices.size(); ++v) {
    const float coords[3] = {vertices[v].x, vertices[v].y, vertices[v].z};
    for (int k = 0; k < 3; ++k) {
      const float x = coords[k];
      const float up = widen ? std::nextafter(x, inf) : x, down = widen ? std::nextafter(x, -inf) : x;
      if (add_round_up(up, margin) < inf && sub_round_down(down, margin) > -inf) continue;
      char text[400];
      std::snprintf(text, sizeof text,
                    "--box-margin %g takes a box past float range: vertex %zu's %c is %g, within the margin of "
                    "float's largest value %g (box i of a box stream is vertices 2i and 2i+1); give a smaller "
                    "margin or move the scene nearer the origin",
                    double(margin), v, "xyz"[k], double(x), double(std::numeric_limits<float>::max()));
      fail_usage(text);
    }
  }
}

}  // namespace cdb
