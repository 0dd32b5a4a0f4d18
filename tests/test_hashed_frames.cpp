// The input's content hash (geometry/hashed_frames.h): known only once every frame of the
// range passed through, equal for equal inputs, different when one coordinate or the
// topology changes.
#include <gtest/gtest.h>

#include <vector>

#include "cdbench/geometry/hashed_frames.h"

namespace cdb {
namespace {

class Frames final : public FrameSource {
 public:
  explicit Frames(double shift) : shift_(shift) {
    topo_.faces = {Tri{0, 1, 2}};
    topo_.num_vertices = 3;
  }
  const Topology& topology() const override { return topo_; }
  uint32_t num_frames() const override { return 3; }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    out = {vec3d{0, 0, double(k)}, vec3d{1, 0, 0}, vec3d{0, 1, k == 2 ? shift_ : 0.0}};
  }
  std::string describe() const override { return "test frames"; }
  Topology topo_;

 private:
  double shift_;
};

std::optional<uint64_t> hash_after_loading(const FrameSource& source, uint32_t first, uint32_t last) {
  const HashedFrames h(source);
  std::vector<vec3d> p;
  for (uint32_t k = first; k < last; ++k) h.positions(k, p);
  return h.input_hash(first, last);
}

TEST(HashedFrames, UnknownUntilEveryFrameLoaded) {
  const Frames f(0);
  const HashedFrames h(f);
  std::vector<vec3d> p;
  h.positions(0, p);
  EXPECT_FALSE(h.input_hash(0, 2));
  h.positions(1, p);
  EXPECT_TRUE(h.input_hash(0, 2));
}

TEST(HashedFrames, SameInputSameHash) {
  EXPECT_EQ(hash_after_loading(Frames(0), 0, 3), hash_after_loading(Frames(0), 0, 3));
}

TEST(HashedFrames, OneCoordinateChangesIt) {
  EXPECT_NE(hash_after_loading(Frames(0), 0, 3), hash_after_loading(Frames(1e-12), 0, 3));
  // Frame 2 outside the range: the same hash.
  EXPECT_EQ(hash_after_loading(Frames(0), 0, 2), hash_after_loading(Frames(1e-12), 0, 2));
}

TEST(HashedFrames, TopologyAndRangeChangeIt) {
  Frames other(0);
  other.topo_.faces = {Tri{0, 2, 1}};
  EXPECT_NE(hash_after_loading(Frames(0), 0, 3), hash_after_loading(other, 0, 3));
  EXPECT_NE(hash_after_loading(Frames(0), 0, 2), hash_after_loading(Frames(0), 1, 3));
}

TEST(ContentHash, HexIsSixteenDigits) { EXPECT_EQ(hash_hex(0xabc), "0000000000000abc"); }

}  // namespace
}  // namespace cdb
