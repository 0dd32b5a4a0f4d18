#pragma once
// A picture as the PNG writer takes it: 8-bit red, green and blue per pixel, rows from the
// top, pixels from the left.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdb {

struct Rgb {
  uint8_t r, g, b;
};

struct RgbImage {
  uint32_t width = 0, height = 0;
  std::vector<Rgb> pixels;  // width * height, row by row

  RgbImage() = default;
  RgbImage(uint32_t w, uint32_t h, Rgb fill) : width(w), height(h), pixels(size_t(w) * h, fill) {}
  Rgb& at(uint32_t x, uint32_t y) { return pixels[size_t(y) * width + x]; }
  const Rgb& at(uint32_t x, uint32_t y) const { return pixels[size_t(y) * width + x]; }
};

}  // namespace cdb
