#include "harness/picture/face_buffer.h"

#include <algorithm>
#include <cmath>

namespace cdb {

FaceBuffer::FaceBuffer(uint32_t width, uint32_t height)
    : width_(width),
      height_(height),
      depth_(size_t(width) * height, std::numeric_limits<float>::infinity()),
      face_(size_t(width) * height, kNoFace) {}

void FaceBuffer::draw(const ScreenPoint& a, const ScreenPoint& b, const ScreenPoint& c, uint32_t face) {
  // Twice the signed area; its sign is the winding, divided out of the edge functions below.
  const double area = double(b.x - a.x) * (c.y - a.y) - double(b.y - a.y) * (c.x - a.x);
  if (area == 0 || !std::isfinite(area)) return;
  // The pixels whose centres lie in the triangle's bounds.
  const double lo_x = std::ceil(std::min({a.x, b.x, c.x}) - 0.5), hi_x = std::floor(std::max({a.x, b.x, c.x}) - 0.5);
  const double lo_y = std::ceil(std::min({a.y, b.y, c.y}) - 0.5), hi_y = std::floor(std::max({a.y, b.y, c.y}) - 0.5);
  if (hi_x < 0 || hi_y < 0 || lo_x >= width_ || lo_y >= height_) return;
  const uint32_t x0 = uint32_t(std::max(lo_x, 0.0)), x1 = uint32_t(std::min(hi_x, double(width_) - 1));
  const uint32_t y0 = uint32_t(std::max(lo_y, 0.0)), y1 = uint32_t(std::min(hi_y, double(height_) - 1));
  const double inv_area = 1 / area;
  for (uint32_t y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (uint32_t x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      // Barycentric weights of a, b and c at the pixel centre; all >= 0 inside.
      const double wa = ((b.x - px) * (c.y - py) - (b.y - py) * (c.x - px)) * inv_area;
      const double wb = ((c.x - px) * (a.y - py) - (c.y - py) * (a.x - px)) * inv_area;
      const double wc = 1 - wa - wb;
      if (wa < 0 || wb < 0 || wc < 0) continue;
      const float depth = float(wa * a.depth + wb * b.depth + wc * c.depth);
      const size_t i = index(x, y);
      if (depth < depth_[i]) {
        depth_[i] = depth;
        face_[i] = face;
      }
    }
  }
}

void FaceBuffer::splat(uint32_t x, uint32_t y, float depth, float tolerance, uint32_t face) {
  if (x >= width_ || y >= height_) return;
  const size_t i = index(x, y);
  if (depth <= depth_[i] + tolerance) {
    depth_[i] = std::min(depth, depth_[i]);
    face_[i] = face;
  }
}

}  // namespace cdb
