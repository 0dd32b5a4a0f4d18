// The procedural scenes: declared sizes, fixed topology, finite and reproducible frames,
// real self-contact in the simulated cloth, and the OBJ writer's round trip.
#include <gtest/gtest.h>
#include <omp.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/error.h"
#include "scenes/generators/generators.h"
#include "scenes/load/frame_cache.h"
#include "scenes/load/obj_sequence.h"
#include "param_name.h"

namespace cdb::test {
namespace {

using nlohmann::json;

struct SizeCase {
  std::string generator;
  json params;
  uint64_t triangles;  // what the scene's documentation says it has
};

uint64_t cloth(uint64_t res) { return 2 * (res - 1) * (res - 1); }
uint64_t ball(uint64_t level) { return 20ull << (2 * level); }

std::vector<SizeCase> size_cases() {
  std::vector<SizeCase> c;
  // Cloth scenes at three resolutions, a few frames each, warm-up shortened.
  for (uint64_t res : {2, 9, 24}) {
    const json base = {{"res", res}, {"frames", 3}, {"warmup", 2}};
    json f = base, b = base, g = base, s = base;
    f["segments"] = 6 + res, f["ball_level"] = 1;
    c.push_back({"funnel", f, cloth(res) + 28 * (6 + res) + ball(1)});
    b["ball_level"] = res % 3;
    c.push_back({"cloth-ball", b, cloth(res) + ball(res % 3)});
    g["segments"] = 3 + res;
    c.push_back({"flag", g, cloth(res) + 16 * (3 + res)});
    s["ball_level"] = 2;
    c.push_back({"sphere", s, cloth(res) + ball(2)});
  }
  for (uint64_t n : {1, 12, 60}) {
    const json p = {{"spheres", n}, {"cones", n / 6}, {"sphere_level", n % 3}, {"cone_segments", 8 + n},
                    {"frames", 3}, {"warmup", 1}};
    c.push_back({"n-body", p, n * ball(n % 3) + (n / 6) * 2 * (8 + n)});
  }
  return c;
}

std::vector<std::vector<vec3d>> all_frames(const FrameSource& s) {
  std::vector<std::vector<vec3d>> f(s.num_frames());
  for (uint32_t k = 0; k < s.num_frames(); ++k) s.positions(k, f[k]);
  return f;
}

bool bitwise_equal(const std::vector<vec3d>& a, const std::vector<vec3d>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(vec3d)) == 0;
}

class SceneSizes : public testing::TestWithParam<SizeCase> {};

TEST_P(SceneSizes, DeclaredCountFixedTopologyFiniteAndReproducible) {
  const SizeCase& c = GetParam();
  auto a = make_generator(c.generator, c.params);
  const Topology& t = a->topology();
  EXPECT_EQ(t.faces.size(), c.triangles) << a->describe();
  EXPECT_NE(a->describe().find(std::to_string(c.triangles) + " triangles"), std::string::npos) << a->describe();
  for (const Tri& f : t.faces) {
    ASSERT_LT(std::max({f.v0, f.v1, f.v2}), t.num_vertices);
    ASSERT_TRUE(f.v0 != f.v1 && f.v1 != f.v2 && f.v0 != f.v2);
  }
  const auto frames = all_frames(*a);
  ASSERT_EQ(frames.size(), 3u);
  for (uint32_t k = 0; k < frames.size(); ++k) EXPECT_NO_THROW(check_frame(frames[k], t, c.generator, k));
  EXPECT_FALSE(bitwise_equal(frames.front(), frames.back())) << "the scene does not move";

  // A second source, and the first one asked again out of order, give the same bits.
  auto b = make_generator(c.generator, c.params);
  const auto again = all_frames(*b);
  std::vector<vec3d> v;
  for (uint32_t k : {2u, 0u, 1u}) {
    EXPECT_TRUE(bitwise_equal(frames[k], again[k])) << "frame " << k;
    a->positions(k, v);
    EXPECT_TRUE(bitwise_equal(frames[k], v)) << "frame " << k << " asked again";
  }
}

INSTANTIATE_TEST_SUITE_P(Generators, SceneSizes, testing::ValuesIn(size_cases()),
                         [](const testing::TestParamInfo<SizeCase>& i) {
                           return param_name(i.param.generator + "_" + std::to_string(i.index));
                         });

// Large enough that the solver's loops run on several threads.
TEST(Scenes, SameBitsOnOneThreadAndOnMany) {
  const json p = {{"res", 90}, {"frames", 2}, {"warmup", 1}, {"substeps", 4}};
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const auto one = all_frames(*make_generator("flag", p));
  omp_set_num_threads(std::max(threads, 4));
  const auto many = all_frames(*make_generator("flag", p));
  omp_set_num_threads(threads);
  for (size_t k = 0; k < one.size(); ++k) EXPECT_TRUE(bitwise_equal(one[k], many[k])) << "frame " << k;
}

TEST(Scenes, SeedChangesTheFolds) {
  const json a = {{"res", 12}, {"frames", 2}, {"warmup", 5}, {"seed", 1}};
  json b = a;
  b["seed"] = 2;
  EXPECT_FALSE(bitwise_equal(all_frames(*make_generator("cloth-ball", a))[1],
                             all_frames(*make_generator("cloth-ball", b))[1]));
}

// Overlapping pairs of triangles in one connected piece whose vertices are more than
// `hops` edges apart: folds touching, not neighbours touching.
size_t fold_contacts(const Topology& t, const std::vector<vec3f>& v, uint32_t hops) {
  std::vector<std::vector<uint32_t>> adj(t.num_vertices);
  for (const Tri& f : t.faces) {
    const uint32_t c[3] = {f.v0, f.v1, f.v2};
    for (int e = 0; e < 3; ++e) {
      adj[c[e]].push_back(c[(e + 1) % 3]);
      adj[c[(e + 1) % 3]].push_back(c[e]);
    }
  }
  std::vector<uint32_t> piece(t.num_vertices, UINT32_MAX);
  for (uint32_t s = 0; s < t.num_vertices; ++s) {
    if (piece[s] != UINT32_MAX) continue;
    std::vector<uint32_t> stack{s};
    piece[s] = s;
    while (!stack.empty()) {
      const uint32_t u = stack.back();
      stack.pop_back();
      for (uint32_t w : adj[u])
        if (piece[w] == UINT32_MAX) piece[w] = s, stack.push_back(w);
    }
  }
  std::vector<uint32_t> mark(t.num_vertices, UINT32_MAX);
  size_t count = 0, stamp = 0;
  for (const PrimPair& p : sweep_oracle_pairs(t, v)) {
    const Tri a = t.faces[p.a], b = t.faces[p.b];
    if (piece[a.v0] != piece[b.v0]) continue;
    // Breadth-first from a's corners, `hops` rings out; b is near if one of its corners is reached.
    ++stamp;
    std::vector<uint32_t> ring{a.v0, a.v1, a.v2}, next;
    for (uint32_t u : ring) mark[u] = uint32_t(stamp);
    for (uint32_t h = 0; h < hops; ++h) {
      next.clear();
      for (uint32_t u : ring)
        for (uint32_t w : adj[u])
          if (mark[w] != stamp) mark[w] = uint32_t(stamp), next.push_back(w);
      ring.swap(next);
    }
    if (mark[b.v0] != stamp && mark[b.v1] != stamp && mark[b.v2] != stamp) ++count;
  }
  return count;
}

TEST(Scenes, FoldContactsCountsOnlyDistantPieces) {
  // A flat cloth has no folds; the same cloth rolled up has.
  auto flat = make_generator("cloth-wave", {{"res", 16}, {"frames", 1}});
  std::vector<vec3f> v;
  flat->frame(0, v);
  for (vec3f& p : v) p.y = 0;
  EXPECT_EQ(fold_contacts(flat->topology(), v, 3), 0u);
  auto rolled = make_generator("cloth-wave", {{"res", 32}, {"frames", 2}});
  rolled->frame(1, v);
  EXPECT_GT(fold_contacts(rolled->topology(), v, 3), 0u);
}

struct ContactCase {
  std::string generator;
  json params;
};

class SceneSelfContact : public testing::TestWithParam<ContactCase> {};

TEST_P(SceneSelfContact, ClothFoldsTouchInTheSecondHalf) {
  auto s = make_generator(GetParam().generator, GetParam().params);
  std::vector<vec3f> v;
  size_t best = 0;
  for (uint32_t k = 0; k < s->num_frames(); ++k) {
    s->frame(k, v);
    if (2 * k >= s->num_frames()) best = std::max(best, fold_contacts(s->topology(), v, 3));
  }
  EXPECT_GT(best, 0u) << s->describe();
}

INSTANTIATE_TEST_SUITE_P(
    Cloth, SceneSelfContact,
    testing::Values(ContactCase{"funnel", json::object()},  // the CI default, as shipped
                    ContactCase{"cloth-ball", {{"res", 32}, {"frames", 30}}},
                    ContactCase{"flag", {{"res", 24}, {"frames", 20}}},
                    ContactCase{"sphere", {{"res", 32}, {"frames", 40}}}),
    [](const testing::TestParamInfo<ContactCase>& i) {
      return param_name(i.param.generator);
    });

TEST(Scenes, UnknownAndOutOfRangeParametersAreRejected) {
  EXPECT_THROW(make_generator("flag", {{"colour", 1}}), Error);
  EXPECT_THROW(make_generator("funnel", {{"res", 1}}), Error);
  EXPECT_THROW(make_generator("n-body", {{"sphere_level", 9}}), Error);
  EXPECT_THROW(make_generator("sphere", {{"frames", 0}}), Error);
}

// A generator that counts the frames it had to simulate.
class CountingSource final : public FrameSource {
 public:
  explicit CountingSource(std::unique_ptr<FrameSource> inner, int* made) : inner_(std::move(inner)), made_(made) {}
  const Topology& topology() const override { return inner_->topology(); }
  uint32_t num_frames() const override { return inner_->num_frames(); }
  std::string describe() const override { return inner_->describe(); }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    ++*made_;
    inner_->positions(k, out);
  }

 private:
  std::unique_ptr<FrameSource> inner_;
  int* made_;
};

TEST(FrameCache, SimulatesOnceThenReadsTheSameBitsAndRedoesABrokenFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("cdb-cache-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  const json params = {{"res", 16}, {"frames", 4}};
  const auto make = [&](int* made) {
    return cache_frames(std::make_unique<CountingSource>(make_generator("funnel", params), made),
                        "funnel " + params.dump(), dir);
  };
  int first = 0, second = 0, third = 0;
  std::vector<std::vector<vec3d>> expected(4);
  {
    auto a = make(&first);
    for (uint32_t k = 0; k < 4; ++k) a->positions(k, expected[k]);
  }
  EXPECT_EQ(first, 4);
  std::vector<vec3d> v;
  {
    auto b = make(&second);
    for (uint32_t k = 0; k < 4; ++k) {
      b->positions(k, v);
      ASSERT_EQ(v.size(), expected[k].size());
      EXPECT_EQ(std::memcmp(v.data(), expected[k].data(), v.size() * sizeof(vec3d)), 0) << "frame " << k;
    }
  }
  EXPECT_EQ(second, 0) << "cached frames were simulated again";
  // A truncated frame file is not trusted: that frame is simulated again, the rest read.
  std::filesystem::path file;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    if (e.path().filename() == "frame_2.f64") file = e.path();
  ASSERT_FALSE(file.empty());
  std::filesystem::resize_file(file, std::filesystem::file_size(file) - 4);
  {
    auto c = make(&third);
    for (uint32_t k = 0; k < 4; ++k) {
      c->positions(k, v);
      EXPECT_EQ(std::memcmp(v.data(), expected[k].data(), v.size() * sizeof(vec3d)), 0) << "frame " << k;
    }
  }
  EXPECT_EQ(third, 1);
  // Other parameters are another scene: nothing is shared.
  int other = 0;
  const json params2 = {{"res", 17}, {"frames", 4}};
  auto d = cache_frames(std::make_unique<CountingSource>(make_generator("funnel", params2), &other),
                        "funnel " + params2.dump(), dir);
  d->positions(0, v);
  EXPECT_EQ(other, 1);
  // Too large for the cache: passed through, nothing stored.
  int big = 0;
  auto e = cache_frames(std::make_unique<CountingSource>(make_generator("funnel", params), &big),
                        "funnel big " + params.dump(), dir, 16);
  e->positions(0, v);
  e->positions(0, v);
  EXPECT_EQ(big, 2);
  std::filesystem::remove_all(dir);
}

TEST(ObjWriter, SequenceReadsBackIdentically) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("cdb_obj_writer_" + std::to_string(::getpid()));
  for (const auto& [name, params] : std::vector<std::pair<std::string, json>>{
           {"funnel", {{"res", 7}, {"frames", 3}, {"warmup", 3}, {"segments", 5}, {"ball_level", 0}}},
           {"n-body", {{"spheres", 4}, {"cones", 1}, {"sphere_level", 0}, {"cone_segments", 5}, {"frames", 2}}},
           {"cloth-ball", {{"res", 7}, {"frames", 2}, {"warmup", 2}, {"ball_level", 0}}},
           {"flag", {{"res", 7}, {"frames", 2}, {"warmup", 2}, {"segments", 5}}},
           {"sphere", {{"res", 7}, {"frames", 2}, {"warmup", 2}, {"ball_level", 0}}},
           {"cloth-wave", {{"res", 8}, {"frames", 2}}},
           {"soup", {{"triangles", 50}, {"frames", 2}}}}) {
    std::filesystem::remove_all(dir);
    auto source = make_generator(name, params);
    write_obj_sequence(*source, dir);
    auto loaded = open_mesh_sequence(dir);
    ASSERT_EQ(loaded->num_frames(), source->num_frames()) << name;
    const Topology& a = source->topology();
    const Topology& b = loaded->topology();
    ASSERT_EQ(a.faces.size(), b.faces.size()) << name;
    std::vector<vec3f> va, vb;
    for (uint32_t k = 0; k < source->num_frames(); ++k) {
      source->frame(k, va);
      loaded->frame(k, vb);
      // The loader may duplicate vertices per face; each face's corners must be the same floats.
      for (size_t f = 0; f < a.faces.size(); ++f) {
        const uint32_t ca[3] = {a.faces[f].v0, a.faces[f].v1, a.faces[f].v2};
        const uint32_t cb[3] = {b.faces[f].v0, b.faces[f].v1, b.faces[f].v2};
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(std::memcmp(&va[ca[c]], &vb[cb[c]], sizeof(vec3f)), 0)
              << name << " frame " << k << " face " << f << " corner " << c;
      }
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cdb::test
