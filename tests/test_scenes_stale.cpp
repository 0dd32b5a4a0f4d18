// The scenes of the cross-system comparison, where fronts go stale (docs/usage.md,
// "Scenes"): spheres, crumple, garment and the large cloth waves, opened as the shipped
// descriptors. Their stated sizes; what each claims of its motion (spheres fall onto the
// floor and pile up; the crumpled sheet's contact grows as far parts of it meet, without
// passing through itself; the garment moves several box sizes a frame; the wave's edge
// curls further every frame); reproducible frames; and every pipeline exact against the
// oracle, at small sizes. The garment reads assimp-testmodels (scripts/install-deps.sh
// --scenes).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "baseline_cases.h"
#include "bvh_cases.h"
#include "error_of.h"
#include "scenes/load/scene.h"
#include "cdbench/narrow/contacts.h"

namespace cdb::test {
namespace {

using nlohmann::json;

constexpr uint32_t kBallVertices = 42;   // icosphere level 1
constexpr uint64_t kBallTriangles = 80;
constexpr uint64_t kBodyTriangles = 5126;  // BCN_Epileptic.X

// 24 balls of 80 triangles through the whole fall (40 frames).
const json kSmallSpheres = {{"spheres", 24}, {"sphere_level", 1}};
const json kSmallCrumple = {{"res", 48}, {"frames", 12}};
// One layer of 16 x 13; a short settle; every 4th simulated frame.
const json kSmallGarment = {{"res", 16}, {"frames", 3}, {"warmup", 1}, {"substeps", 4}, {"stride", 4}};

// Uncached, so that every open generates: frames read back from the cache would hide a
// difference between two runs.
Scene open(const std::string& name, const json& sets = json::object()) {
  ::setenv("CDBENCH_FRAME_CACHE", "off", 1);
  return open_scene(name, default_scenes_dir(), sets);
}

json with(json base, const json& more) {
  base.update(more);
  return base;
}

bool bitwise(const std::vector<vec3f>& a, const std::vector<vec3f>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(vec3f)) == 0;
}

float axis(const vec3f& p, int a) { return a == 0 ? p.x : a == 1 ? p.y : p.z; }

// How far a face's centroid moves from `a` to `b`, in sizes of its box at `a` (the box's
// longest side): the median over faces [0, faces).
double median_motion_in_boxes(const Topology& t, uint32_t faces, const std::vector<vec3f>& a,
                              const std::vector<vec3f>& b) {
  std::vector<double> r(faces);
  for (uint32_t f = 0; f < faces; ++f) {
    const uint32_t c[3] = {t.faces[f].v0, t.faces[f].v1, t.faces[f].v2};
    double moved = 0, side = 0;
    for (int x = 0; x < 3; ++x) {
      const double pa = axis(a[c[0]], x), qa = axis(a[c[1]], x), ra = axis(a[c[2]], x);
      const double d = (double(axis(b[c[0]], x)) + axis(b[c[1]], x) + axis(b[c[2]], x) - pa - qa - ra) / 3;
      moved += d * d;
      side = std::max(side, std::max({pa, qa, ra}) - std::min({pa, qa, ra}));
    }
    r[f] = std::sqrt(moved) / std::max(side, 1e-12);
  }
  std::nth_element(r.begin(), r.begin() + faces / 2, r.end());
  return r[faces / 2];
}

TEST(StaleScenes, DefaultSizesAreTheComparisons) {
  // Opening builds the topology only; no frame is generated.
  const struct {
    const char* name;
    uint64_t triangles;
    uint32_t frames;
    const char* stated;
  } scenes[] = {{"spheres", 150 * 320, 40, "48,000 triangles"},
                {"cloth-wave-522k", 2 * 511 * 511, 20, "522,242 triangles"},
                {"cloth-wave-1m", 2 * 707 * 707, 5, "999,698 triangles"},
                {"crumple", 2 * 255 * 255, 40, "130,050 triangles"},
                {"garment", 2 * 300 * 240 + kBodyTriangles, 21, "149,126"},
                {"garment-avatar", 2 * 300 * 240 + 16 * kBodyTriangles, 21, "226,016"}};
  for (const auto& c : scenes) {
    SCOPED_TRACE(c.name);
    const Scene s = open(c.name);
    EXPECT_EQ(s.source->topology().faces.size(), c.triangles);
    EXPECT_EQ(s.source->num_frames(), c.frames);
    EXPECT_NE(s.description.find(c.stated), std::string::npos) << s.description;
  }
}

TEST(StaleScenes, SmallSizesThroughSet) {
  EXPECT_EQ(open("spheres", kSmallSpheres).source->topology().faces.size(), 24 * kBallTriangles);
  EXPECT_EQ(open("crumple", kSmallCrumple).source->topology().faces.size(), 2u * 47 * 47);
  EXPECT_EQ(open("cloth-wave-522k", {{"res", 24}}).source->topology().faces.size(), 2u * 23 * 23);
  const Scene g = open("garment", kSmallGarment);
  EXPECT_EQ(g.source->topology().faces.size(), 2u * 16 * 12 + kBodyTriangles);
  EXPECT_NE(g.description.find("one in 4 simulated frames"), std::string::npos) << g.description;
}

// Per ball: the centre (its vertices' mean: an icosphere's vertices come in opposite
// pairs), its radius and its lowest point.
struct Ball {
  vec3d centre;
  double radius, bottom;
};

std::vector<Ball> balls(const std::vector<vec3f>& v) {
  std::vector<Ball> out(v.size() / kBallVertices);
  for (size_t b = 0; b < out.size(); ++b) {
    vec3d c{0, 0, 0};
    for (uint32_t i = 0; i < kBallVertices; ++i) {
      const vec3f& p = v[b * kBallVertices + i];
      c = {c.x + p.x / kBallVertices, c.y + p.y / kBallVertices, c.z + p.z / kBallVertices};
    }
    double r = 0;
    for (uint32_t i = 0; i < kBallVertices; ++i) {
      const vec3f& p = v[b * kBallVertices + i];
      r = std::max(r, std::hypot(p.x - c.x, p.y - c.y, p.z - c.z));
    }
    out[b] = {c, r, c.y - r};
  }
  return out;
}

// The balls fall, bounce and come to rest in a pile: many on the floor, none below it (the
// pile's weight does not press one through), others resting on the balls under them.
TEST(StaleScenes, SpheresFallBounceAndPileUpAboveTheFloor) {
  const Scene s = open("spheres", kSmallSpheres);
  const SceneFrames frames = frames_of(*s.source);
  std::vector<std::vector<Ball>> b;
  for (const auto& v : frames.frames) b.push_back(balls(v));
  const size_t n = b[0].size(), last = b.size() - 1;
  ASSERT_EQ(n, 24u);
  double floor = 1e300, radius = 0;
  for (const auto& f : b)
    for (const Ball& x : f) floor = std::min(floor, x.bottom), radius = std::max(radius, x.radius);
  size_t on_floor = 0, on_others = 0, bounced = 0;
  double height_then = 0, height_now = 0;
  for (size_t i = 0; i < n; ++i) {
    const Ball& x = b[last][i];
    height_then += b[0][i].centre.y / n, height_now += x.centre.y / n;
    // Floats: a ball on the floor is there to their rounding.
    if (x.bottom <= floor + 1e-6 * radius) ++on_floor;
    bool touching = false;
    for (size_t j = 0; j < n; ++j) {
      const Ball& y = b[last][j];
      const double d = std::hypot(x.centre.x - y.centre.x, x.centre.y - y.centre.y, x.centre.z - y.centre.z);
      touching |= j != i && y.centre.y < x.centre.y && d < x.radius + y.radius + 1e-3 * radius;
    }
    const double moved = std::abs(x.centre.y - b[last - 1][i].centre.y);
    if (x.bottom > floor + 0.5 * x.radius && touching && moved < 0.1 * x.radius) ++on_others;
    // Falling, then rising: a bounce.
    for (size_t k = 1; k + 1 < b.size(); ++k)
      if (b[k][i].centre.y < b[k - 1][i].centre.y - 0.05 * radius &&
          b[k + 1][i].centre.y > b[k][i].centre.y + 0.05 * radius) {
        ++bounced;
        break;
      }
  }
  EXPECT_GE(on_floor, n / 4) << "few balls rest on the lowest level reached: one sank through the floor";
  EXPECT_GE(on_others, n / 4) << "the balls do not pile up";
  EXPECT_GE(bounced, n / 4) << "the balls do not bounce";
  EXPECT_LT(height_now, height_then - radius) << "the balls do not fall";
  const size_t pairs_then = sweep_oracle_pairs(frames.topology, frames.frames[0]).size();
  EXPECT_GT(sweep_oracle_pairs(frames.topology, frames.frames[last]).size(), pairs_then + 50) << "contacts do not grow";
}

// Pairs of the sheet's triangles whose cells are more than `cells` apart in the sheet:
// folds lying on each other, not neighbours touching.
size_t far_in_sheet(const std::vector<PrimPair>& pairs, uint32_t res, uint32_t cells) {
  size_t far = 0;
  for (const PrimPair& p : pairs) {
    const uint32_t a = p.a / 2, b = p.b / 2;
    const int64_t di = int64_t(a % (res - 1)) - int64_t(b % (res - 1));
    const int64_t dj = int64_t(a / (res - 1)) - int64_t(b / (res - 1));
    far += uint64_t(std::max(std::abs(di), std::abs(dj))) > cells;
  }
  return far;
}

// The sheet's contact grows frame by frame as its folds lie over each other, far parts of
// it come to touch, and it ends squeezed, its area kept about the same (as cloth's).
TEST(StaleScenes, CrumpleContactGrowsAsFarPartsMeet) {
  const Scene s = open("crumple", kSmallCrumple);
  const ExactFrames e = exact_frames(*s.source);
  const uint32_t res = 48, last = e.num_frames() - 1;
  for (uint32_t k = 1; k <= last; ++k)
    EXPECT_GT(e.pairs[k].size(), e.pairs[k - 1].size()) << "frame " << k;
  EXPECT_GT(e.pairs[last].size(), 1.3 * e.pairs[0].size());
  EXPECT_EQ(far_in_sheet(e.pairs[0], res, 4), 0u);
  EXPECT_GT(far_in_sheet(e.pairs[last], res, 4), e.pairs[last].size() / 100) << "far parts do not meet";
  for (uint32_t k = 0; k <= last; ++k) {
    const auto& v = e.vertices[k];
    double area = 0;
    for (const Tri& f : e.topology.faces) {
      const vec3f a = v[f.v0], b = v[f.v1], c = v[f.v2];
      const double u[3] = {b.x - a.x, b.y - a.y, b.z - a.z}, w[3] = {c.x - a.x, c.y - a.y, c.z - a.z};
      area += 0.5 * std::hypot(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]);
    }
    EXPECT_NEAR(area, 1.0, 0.2) << "frame " << k;
  }
  float lo[2] = {1e30f, 1e30f}, hi[2] = {-1e30f, -1e30f};
  for (const vec3f& p : e.vertices[last]) {
    lo[0] = std::min(lo[0], p.x), hi[0] = std::max(hi[0], p.x);
    lo[1] = std::min(lo[1], p.z), hi[1] = std::max(hi[1], p.z);
  }
  EXPECT_LT(hi[0] - lo[0], 0.6f);
  EXPECT_LT(hi[1] - lo[1], 0.6f);
}

// The sheet is carried by a one-to-one flow, so only its triangles, flat where the sheet
// curves, can cut each other where folds touch: fewer at a finer mesh, and a tiny share of
// the pairs. Two frames: the start and the end of the run.
TEST(StaleScenes, CrumpleHardlyPassesThroughItself) {
  size_t crossing[2], pairs = 0;
  const uint32_t res[2] = {48, 96};
  for (int r = 0; r < 2; ++r) {
    const Scene s = open("crumple", {{"res", res[r]}, {"frames", 2}});
    std::vector<vec3f> v;
    s.source->frame(1, v);
    const Topology& t = s.source->topology();
    crossing[r] = count_true_contacts(t.faces, v, sweep_oracle_pairs(t, v, true));
    pairs = sweep_oracle_pairs(t, v).size();
  }
  EXPECT_LT(crossing[1], crossing[0]);
  EXPECT_LT(double(crossing[1]), 5e-4 * double(pairs)) << crossing[1] << " of " << pairs;
}

// Frame k of the garment is frame k * stride of the same dance: the body is sampled there,
// bit for bit, and the cloth moves stride times as far a frame, several of its boxes.
TEST(StaleScenes, GarmentFramesAreEveryStrideThSimulatedFrame) {
  const uint32_t stride = 8, frames = 4;
  const Scene g = open("garment", with(kSmallGarment, {{"stride", stride}, {"frames", frames}}));
  const Scene f = open("garment", with(kSmallGarment, {{"stride", 1}, {"frames", stride * (frames - 1) + 1},
                                                       {"warmup", stride}}));
  const Topology& t = g.source->topology();
  const uint32_t cloth = t.objects[0].num_faces;
  ASSERT_EQ(t.objects[0].name, "cloth");
  uint32_t body = t.num_vertices;
  for (uint32_t i = cloth; i < t.faces.size(); ++i) body = std::min({body, t.faces[i].v0, t.faces[i].v1, t.faces[i].v2});
  const auto coarse = frames_of(*g.source).frames;
  const auto fine = frames_of(*f.source).frames;
  double coarse_motion = 0, fine_motion = 0;
  for (uint32_t k = 0; k < frames; ++k) {
    EXPECT_EQ(std::memcmp(coarse[k].data() + body, fine[k * stride].data() + body,
                          (t.num_vertices - body) * sizeof(vec3f)),
              0)
        << "frame " << k;
    if (k == 0) continue;
    coarse_motion += median_motion_in_boxes(t, cloth, coarse[k - 1], coarse[k]) / (frames - 1);
  }
  for (uint32_t k = 1; k < fine.size(); ++k)
    fine_motion += median_motion_in_boxes(t, cloth, fine[k - 1], fine[k]) / (fine.size() - 1);
  EXPECT_GT(coarse_motion, 3 * fine_motion);
  EXPECT_GT(coarse_motion, 0.4);
}

double area(const Tri& t, const std::vector<vec3f>& v) {
  const vec3f a = v[t.v0], b = v[t.v1], c = v[t.v2];
  const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, wx = c.x - a.x, wy = c.y - a.y, wz = c.z - a.z;
  return 0.5 * std::hypot(uy * wz - uz * wy, uz * wx - ux * wz, ux * wy - uy * wx);
}

// The garment with its avatar is the garment's skirt, moving bit for bit as the garment's,
// on the same body surface in 4^levels as many triangles (each vertex of the finer body the
// coarse one's or a midpoint of two earlier ones), with the skirt's self and skirt-body
// queries declared.
TEST(StaleScenes, GarmentAvatarIsTheGarmentOnAFinerBodyOfTheSameSurface) {
  const Scene g = open("garment", kSmallGarment);
  const Scene a = open("garment-avatar", with(kSmallGarment, {{"body_subdivisions", 2}}));
  const Topology& tg = g.source->topology();
  const Topology& ta = a.source->topology();
  ASSERT_EQ(ta.objects.size(), 2u);
  EXPECT_EQ(ta.objects[0].name, "cloth");
  EXPECT_EQ(ta.objects[1].name, "body");
  EXPECT_TRUE(ta.queries.declared);
  const uint32_t cloth = ta.objects[0].num_faces;
  ASSERT_EQ(cloth, tg.objects[0].num_faces);
  EXPECT_EQ(ta.objects[1].num_faces, 16 * kBodyTriangles);
  const auto coarse = frames_of(*g.source).frames;
  const auto fine = frames_of(*a.source).frames;
  ASSERT_EQ(coarse.size(), fine.size());
  for (size_t k = 0; k < fine.size(); ++k) {
    SCOPED_TRACE(k);
    // Every garment vertex (the skirt's, then the coarse body's) comes first, the same bits.
    EXPECT_EQ(std::memcmp(coarse[k].data(), fine[k].data(), tg.num_vertices * sizeof(vec3f)), 0);
    double coarse_area = 0, fine_area = 0;
    for (uint32_t f = cloth; f < tg.faces.size(); ++f) coarse_area += area(tg.faces[f], coarse[k]);
    for (uint32_t f = cloth; f < ta.faces.size(); ++f) fine_area += area(ta.faces[f], fine[k]);
    EXPECT_NEAR(fine_area, coarse_area, 1e-5 * coarse_area);
  }
  EXPECT_NE(error_of([] { open("garment-avatar", {{"body_subdivisions", 4}}); }).find("out of range"),
            std::string::npos);
}

// The total turn of the sheet's middle row, from its first edge to its last: the wave's
// small slopes and the roll's turns.
double roll_turn(const std::vector<vec3d>& v, uint32_t res) {
  const size_t row = size_t(res / 2) * res;
  double turn = 0, previous = std::atan2(v[row + 1].y - v[row].y, v[row + 1].x - v[row].x);
  for (uint32_t i = 1; i + 1 < res; ++i) {
    const double a = std::atan2(v[row + i + 1].y - v[row + i].y, v[row + i + 1].x - v[row + i].x);
    turn += std::remainder(a - previous, 2 * M_PI);
    previous = a;
  }
  return turn;
}

// At their full sizes: the roll eats further into the sheet every frame (its front comes
// back along x), and by the end the edge has turned over more than a full turn.
TEST(StaleScenes, ClothWaveEdgeCurlsFurtherEveryFrame) {
  for (const auto& [name, res] : {std::pair{"cloth-wave-522k", 512u}, std::pair{"cloth-wave-1m", 708u}}) {
    SCOPED_TRACE(name);
    const Scene s = open(name);
    std::vector<vec3d> v;
    double front = 1e300, first_turn = 0, turn = 0;
    for (uint32_t k = 0; k < s.source->num_frames(); ++k) {
      s.source->positions(k, v);
      double x = -1e300;
      for (const vec3d& p : v) x = std::max(x, p.x);
      EXPECT_LT(x, front - 0.01) << "frame " << k;
      front = x;
      turn = roll_turn(v, res);
      if (k == 0) first_turn = turn;
    }
    EXPECT_GT(turn, 2 * M_PI) << "the edge does not roll over";
    EXPECT_GT(turn, first_turn + 3) << "the edge does not curl further";
  }
}

// Frames made on one thread and again on several, asked out of order, are the same bits.
TEST(StaleScenes, SameBitsOpenedAgainOnMoreThreadsAndAskedOutOfOrder) {
  for (const auto& [name, params] : {std::pair{std::string("spheres"), with(kSmallSpheres, {{"frames", 3}})},
                                     std::pair{std::string("crumple"), with(kSmallCrumple, {{"frames", 3}})},
                                     std::pair{std::string("garment"), kSmallGarment}}) {
    SCOPED_TRACE(name);
    const int threads = omp_get_max_threads();
    omp_set_num_threads(1);
    const SceneFrames one = frames_of(*open(name, params).source);
    omp_set_num_threads(std::max(threads, 4));
    const Scene again = open(name, params);
    std::vector<vec3f> v;
    for (uint32_t k : {2u, 0u, 1u}) {
      again.source->frame(k, v);
      EXPECT_TRUE(bitwise(one.frames[k], v)) << "frame " << k;
    }
    omp_set_num_threads(threads);
    EXPECT_FALSE(bitwise(one.frames.front(), one.frames.back())) << "the scene does not move";
  }
}

TEST(StaleScenes, BadParametersSayWhich) {
  EXPECT_NE(error_of([] { open("crumple", {{"squeeze", 0}}); }).find("squeeze"), std::string::npos);
  EXPECT_NE(error_of([] { open("crumple", {{"start", 1}}); }).find("start"), std::string::npos);
  EXPECT_NE(error_of([] { open("spheres", {{"restitution", 2}}); }).find("restitution"), std::string::npos);
  EXPECT_NE(error_of([] { open("spheres", {{"passes", 0}}); }).find("out of range"), std::string::npos);
  EXPECT_NE(error_of([] { open("garment", {{"stride", 0}}); }).find("out of range"), std::string::npos);
}

// Every pipeline reports the oracle's pairs on every frame, with a pair buffer too small at
// first so that it must grow.
void expect_all_pipelines_exact(const std::string& name, const json& params) {
  Scene s = open(name, params);
  check_pipelines_on(config_for("cpu", 0.5, 0.05, 2), *s.source, 8000);
}

TEST(StaleScenesExact, Spheres) { expect_all_pipelines_exact("spheres", with(kSmallSpheres, {{"frames", 6}})); }
TEST(StaleScenesExact, Crumple) { expect_all_pipelines_exact("crumple", {{"res", 24}, {"frames", 6}}); }
TEST(StaleScenesExact, Garment) { expect_all_pipelines_exact("garment", kSmallGarment); }
TEST(StaleScenesExact, GarmentAvatarQueries) {
  Scene s = open("garment-avatar", with(kSmallGarment, {{"body_subdivisions", 1}}));
  check_declared_queries("cpu", *s.source);
  // The body in the second tree (--split-objects queries).
  ASSERT_TRUE(split_objects(s.source->topology(), SplitRule::queries).rigid_tree_deforms);
  PipelineConfig cfg = config_for("cpu", 0.5, 0.05, 2);
  cfg.tree.split = SplitRule::queries;
  check_pipelines_on(cfg, *s.source);
}
TEST(StaleScenesExact, ClothWave) { expect_all_pipelines_exact("cloth-wave-522k", {{"res", 24}, {"frames", 4}}); }

}  // namespace
}  // namespace cdb::test
