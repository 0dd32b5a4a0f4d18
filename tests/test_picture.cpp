// The picture's rasterizer (harness/picture/face_buffer.h): which pixel centres a triangle
// covers, the nearer of two triangles winning, and the splat of one too small to cover any.
#include <gtest/gtest.h>

#include "harness/picture/face_buffer.h"

namespace cdb {
namespace {

TEST(FaceBuffer, TriangleCoversThePixelCentresInside) {
  FaceBuffer buffer(4, 4);
  // The lower-left half of the 4x4 square, its diagonal through pixel corners: the centres
  // (x + 0.5, y + 0.5) with x <= y lie inside, those with x > y outside.
  buffer.draw({0, 0, 1}, {0, 4, 1}, {4, 4, 1}, 7);
  for (uint32_t y = 0; y < 4; ++y)
    for (uint32_t x = 0; x < 4; ++x) EXPECT_EQ(buffer.face(x, y), x <= y ? 7u : kNoFace) << x << "," << y;
}

TEST(FaceBuffer, WindingDoesNotMatterAndTheNearerWins) {
  FaceBuffer buffer(2, 2);
  buffer.draw({0, 0, 5}, {2, 0, 5}, {0, 2, 5}, 1);
  buffer.draw({0, 0, 2}, {0, 2, 2}, {2, 0, 2}, 2);  // the other winding, nearer
  buffer.draw({0, 0, 9}, {2, 0, 9}, {0, 2, 9}, 3);  // farther: hidden
  EXPECT_EQ(buffer.face(0, 0), 2u);
  EXPECT_FLOAT_EQ(buffer.depth(0, 0), 2.0f);
  EXPECT_EQ(buffer.face(1, 1), kNoFace);
}

TEST(FaceBuffer, TinyTriangleCoversNoCentreButSplats) {
  FaceBuffer buffer(2, 2);
  buffer.draw({0, 0, 4}, {2, 0, 4}, {0, 2, 4}, 1);
  buffer.draw({0.1f, 0.1f, 3}, {0.2f, 0.1f, 3}, {0.1f, 0.2f, 3}, 2);
  EXPECT_EQ(buffer.face(0, 0), 1u);
  buffer.splat(0, 0, 5.0f, 0.5f, 2);  // more than the tolerance behind: hidden
  EXPECT_EQ(buffer.face(0, 0), 1u);
  buffer.splat(0, 0, 4.25f, 0.5f, 2);
  EXPECT_EQ(buffer.face(0, 0), 2u);
}

}  // namespace
}  // namespace cdb
