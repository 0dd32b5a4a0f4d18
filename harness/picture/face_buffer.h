#pragma once
// A z-buffer that keeps, per pixel, the nearest triangle drawn over its centre: the
// picture's rasterizer. Triangles come in screen space (orthographic, so depth is linear
// over a triangle), and the picture is shaded afterwards from the triangle of each pixel,
// once per pixel rather than once per triangle fragment.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdb {

// A vertex on the screen: x to the right and y down, in pixels (pixel (i, j) spans
// [i, i+1) x [j, j+1), its centre at (i + 0.5, j + 0.5)); depth grows away from the viewer.
struct ScreenPoint {
  float x, y, depth;
};

inline constexpr uint32_t kNoFace = std::numeric_limits<uint32_t>::max();

class FaceBuffer {
 public:
  FaceBuffer(uint32_t width, uint32_t height);

  // Writes `face` into every pixel whose centre the triangle covers (edges included) and
  // where it lies nearer than what the pixel holds. Either winding; a triangle of no area
  // covers nothing.
  void draw(const ScreenPoint& a, const ScreenPoint& b, const ScreenPoint& c, uint32_t face);

  // Sets pixel (x, y) to `face` when `depth` is at most `tolerance` behind what it holds:
  // a triangle too small to cover a pixel centre still shows, where nothing hides it.
  void splat(uint32_t x, uint32_t y, float depth, float tolerance, uint32_t face);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // kNoFace where no triangle covers the pixel.
  uint32_t face(uint32_t x, uint32_t y) const { return face_[index(x, y)]; }
  float depth(uint32_t x, uint32_t y) const { return depth_[index(x, y)]; }

 private:
  size_t index(uint32_t x, uint32_t y) const { return size_t(y) * width_ + x; }

  uint32_t width_, height_;
  std::vector<float> depth_;
  std::vector<uint32_t> face_;
};

}  // namespace cdb
