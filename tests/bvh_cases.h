#pragma once
// The property tests of the ordered LBVH and its self query, written once over the
// executor; test_bvh_host.cpp runs them on the host executor, test_bvh_cuda.cu on CUDA.
#include <gtest/gtest.h>

#include <algorithm>
#include <utility>
#include <cstring>
#include <memory>
#include <set>
#include <string>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/bvh/build.h"
#include "cdbench/bvh/order.h"
#include "cdbench/bvh/refit.h"
#include "cdbench/bvh/restructure.h"
#include "cdbench/bvh/self_query.h"
#include "cdbench/geometry/mesh_pieces.h"
#include "bvh_checks.h"
#include "cdbench/core/pair_set.h"
#include "scenes/generators/generators.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/plan_record.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

struct SoupCase {
  uint64_t triangles;
  std::string distribution;
  double scale;
  double duplicates;
  MortonBits bits;
};

inline std::string case_name(const testing::TestParamInfo<SoupCase>& info) {
  const SoupCase& c = info.param;
  std::string s = "n" + std::to_string(c.triangles) + "_" + c.distribution;
  s += c.scale == 1.0 ? "_unit" : c.scale < 1.0 ? "_tiny" : "_huge";
  if (c.duplicates > 0) s += "_dups";
  s += c.bits == MortonBits::b30 ? "_m30" : "_m63";
  return s;
}

// Sizes 0..100000 over uniform, clustered and identical centroids, duplicates, and
// coordinates scaled to 1e-20 and 1e+20. Identical centroids make every box overlap every
// other (N^2/2 pairs), so they stop at 2000 triangles.
inline std::vector<SoupCase> soup_cases() {
  std::vector<SoupCase> cases;
  for (uint64_t n : {0ull, 1ull, 2ull, 3ull, 7ull, 1000ull, 100000ull})
    for (const char* dist : {"uniform", "clustered", "identical"})
      for (double scale : {1.0, 1e-20, 1e20}) {
        if (std::string(dist) == "identical" && n > 2000) continue;
        const bool small_variant = scale != 1.0 && n == 100000;
        if (small_variant) continue;  // scale variants run at 1000 and below
        cases.push_back({n, dist, scale, 0.0, MortonBits::b63});
      }
  cases.push_back({2000, "identical", 1.0, 0.0, MortonBits::b63});
  cases.push_back({1000, "uniform", 1.0, 0.3, MortonBits::b63});
  cases.push_back({1000, "clustered", 1.0, 0.5, MortonBits::b30});
  cases.push_back({100000, "uniform", 1.0, 0.1, MortonBits::b30});
  cases.push_back({100000, "clustered", 1e20, 0.0, MortonBits::b30});
  return cases;
}

inline std::unique_ptr<FrameSource> soup_source(const SoupCase& c) {
  return make_generator("soup", {{"triangles", c.triangles},
                                 {"distribution", c.distribution},
                                 {"scale", c.scale},
                                 {"duplicates", c.duplicates},
                                 {"frames", 3},
                                 {"seed", 11 + c.triangles}});
}

// A scene's faces on the executor, one frame's vertices at a time, and a pair buffer with
// its counter for direct queries: what the tree-level tests set up.
template <class Exec>
struct TestMesh {
  TestMesh(Exec& exec, const Topology& topo)
      : vertices(exec.memory(), "test.vertices"),
        faces(exec.memory(), "test.faces"),
        pairs(exec.memory(), "test.pairs"),
        count(exec.memory(), "test.count"),
        num_faces(uint32_t(topo.faces.size())) {
    vertices.reserve(topo.num_vertices);
    faces.reserve(topo.faces.size());
    count.reserve(1);
    exec.copy_from_host(faces.data(), topo.faces.data(), topo.faces.size());
  }
  void upload(Exec& exec, const std::vector<vec3f>& v) { exec.copy_from_host(vertices.data(), v.data(), v.size()); }
  MeshView view() const { return {vertices.data(), faces.data(), num_faces}; }

  Array<vec3f> vertices;
  Array<Tri> faces;
  Array<PrimPair> pairs;
  Array<unsigned long long> count;
  uint32_t num_faces;
};

// The stackless self query on `bvh` against the sweep oracle for these positions.
template <class Exec>
void expect_self_query_exact(Exec& exec, const Lbvh<Exec>& bvh, const Topology& topo,
                             const std::vector<vec3f>& v, Array<PrimPair>& pairs,
                             Array<unsigned long long>& count, uint32_t frame) {
  const std::vector<PrimPair> expected = sweep_oracle_pairs(topo, v);
  pairs.reserve(expected.size() + 1);
  exec.fill(count.data(), 1, 0ull);
  self_query(exec, bvh.view(), PairSink{pairs.data(), count.data(), pairs.capacity()});
  unsigned long long found = 0;
  exec.copy_to_host(&found, count.data(), 1);
  ASSERT_EQ(found, expected.size()) << "frame " << frame;
  std::vector<PrimPair> got(found);
  exec.copy_to_host(got.data(), pairs.data(), found);
  sort_by_pair_key(got);
  const PairSetDiff d = diff_pair_sets(expected, got);
  ASSERT_TRUE(d.equal()) << "frame " << frame << ": " << d.missing_count << " missing, "
                         << d.unexpected_count << " unexpected";
}

// Two downloads of one tree hold the same boxes, leaves and internal nodes, bit for bit.
inline bool same_boxes(const HostBvh& a, const HostBvh& b) {
  auto same = [](const std::vector<vec4f>& x, const std::vector<vec4f>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(vec4f)) == 0;
  };
  return same(a.leaf_lo, b.leaf_lo) && same(a.leaf_hi, b.leaf_hi) && same(a.node_lo, b.node_lo) &&
         same(a.node_hi, b.node_hi);
}

// The refit's tiles (bvh/refit_index.h) are the treelets: they cut [0, n) into consecutive
// ranges, each the leaves of a subtree of at most kRefitTile leaves whose parent has more
// (or of the root), one tile per such subtree.
template <class Exec>
void expect_treelet_tiles(Exec& exec, const Lbvh<Exec>& bvh, const HostBvh& h, const std::string& where) {
  if (h.n == 0) return;
  uint32_t count = 0;
  exec.copy_to_host(&count, bvh.tile_count.data(), 1);
  ASSERT_GE(count, 1u) << where;
  ASSERT_LE(count, h.n) << where;
  std::vector<uint32_t> first(count + 1);
  exec.copy_to_host(first.data(), bvh.tile_first.data(), first.size());
  EXPECT_EQ(first.front(), 0u) << where;
  EXPECT_EQ(first.back(), h.n) << where;
  const auto size = [&](uint32_t k) { return h.node_last[k] - h.node_first[k] + 1; };
  // [first, last] of every treelet root: internal nodes within a tile's size whose parent
  // is not, and leaves hanging from nodes larger than a tile.
  std::vector<std::pair<uint32_t, uint32_t>> treelets;
  if (h.n == 1) treelets.push_back({0, 0});
  for (uint32_t k = 0; k + 1 < h.n; ++k) {
    const uint32_t p = h.node_parent[k];
    if (size(k) <= kRefitTile && (p == kNoNode || size(p) > kRefitTile)) treelets.push_back({h.node_first[k], h.node_last[k]});
    if (size(k) > kRefitTile)
      for (uint32_t c : {h.node_left[k], h.node_right[k]})
        if (is_leaf(c)) treelets.push_back({ref_index(c), ref_index(c)});
  }
  std::sort(treelets.begin(), treelets.end());
  ASSERT_EQ(treelets.size(), count) << where << ": tiles against treelets";
  for (uint32_t t = 0; t < count; ++t) {
    EXPECT_LT(first[t], first[t + 1]) << where << ", tile " << t;
    EXPECT_LE(first[t + 1] - first[t], kRefitTile) << where << ", tile " << t;
    EXPECT_EQ(first[t], treelets[t].first) << where << ", tile " << t;
    EXPECT_EQ(first[t + 1] - 1, treelets[t].second) << where << ", tile " << t;
  }
}

// Every refit gives the same boxes, bit for bit: a box is a min/max merge whatever the order
// of merges. The tiles by climbing (bvh/refit.h) or level by level (bvh/refit_levels.h, whose
// tables exist where bvh.refit_levels was on at the build), the spanning top in one block
// (bvh/refit_top.h) or handed over between blocks. Leaves bvh.refit_levels as it found it.
template <class Exec>
void expect_refits_agree(Exec& exec, Lbvh<Exec>& bvh, const MeshView& mesh, const std::string& where) {
  const uint32_t top_max_leaves = bvh.refit_top_max_leaves;
  const bool levels = bvh.refit_levels;
  bvh.refit_levels = false;
  bvh.refit_top_max_leaves = 0;
  refit(exec, bvh, mesh);
  const HostBvh between_blocks = download(exec, bvh);
  bvh.refit_top_max_leaves = top_max_leaves;
  refit(exec, bvh, mesh);
  const HostBvh one_block = download(exec, bvh);
  EXPECT_TRUE(same_boxes(between_blocks, one_block)) << where << ": boxes differ between the two refits of the top";
  if (levels) {
    bvh.refit_levels = true;
    refit(exec, bvh, mesh);
    EXPECT_TRUE(same_boxes(one_block, download(exec, bvh))) << where << ": the level refit's boxes differ";
    bvh.refit_top_max_leaves = 0;
    refit(exec, bvh, mesh);
    EXPECT_TRUE(same_boxes(one_block, download(exec, bvh)))
        << where << ": the level refit's boxes differ with the top handed over between blocks";
    bvh.refit_top_max_leaves = top_max_leaves;
  }
  bvh.refit_levels = levels;
}

// Build + order on frame 0, refit on frames 1 and 2: after each, the tree must pass every
// reference check and the self query must report exactly the oracle's pairs; on refit frames
// every refit agrees (expect_refits_agree), and the level refit (bvh/refit_levels.h) is the
// one the checks see.
// `shared_slots`: the refit top's shared-memory slots (Lbvh::refit_top_shared_slots); below
// the default the case must spill past them. `top_max_leaves`: Lbvh::refit_top_max_leaves.
template <class Exec>
void check_soup_case(const SoupCase& c, uint32_t shared_slots = kRefitTopSharedSlots,
                     uint32_t top_max_leaves = kRefitTopMaxLeaves) {
  auto source = soup_source(c);
  const Topology& topo = source->topology();
  Exec exec;
  Lbvh<Exec> bvh(exec);
  bvh.refit_top_shared_slots = shared_slots;
  bvh.refit_top_max_leaves = top_max_leaves;
  bvh.refit_levels = true;
  TestMesh<Exec> m(exec, topo);
  const MeshView mesh = m.view();
  std::vector<vec3f> v;
  for (uint32_t f = 0; f < source->num_frames(); ++f) {
    source->frame(f, v);
    m.upload(exec, v);
    if (f == 0) {
      build_hierarchy(exec, bvh, mesh, c.bits);
      order_depth_first(exec, bvh);
      if (shared_slots < kRefitTopSharedSlots) {
        uint32_t spanning = 0;
        exec.copy_to_host(&spanning, bvh.span_count.data(), 1);
        ASSERT_GT(spanning, 4 * shared_slots) << "the case no longer spills past shared memory";
      }
    } else {
      expect_refits_agree(exec, bvh, mesh, "frame " + std::to_string(f));
      refit(exec, bvh, mesh);
    }
    const HostBvh h = download(exec, bvh);
    ASSERT_EQ(check_bvh(h, topo, v), "") << "frame " << f;
    if (f == 0) expect_treelet_tiles(exec, bvh, h, "frame 0");

    expect_self_query_exact(exec, bvh, topo, v, m.pairs, m.count, f);
    if (testing::Test::HasFatalFailure()) return;
  }
}

// A scene's frames with the sweep oracle's pairs on each, computed once for every pipeline
// and setting checked on the scene: the oracle runs on the host and costs more than most
// pipelines, so the tests that run many pipelines over one scene share it.
struct ExactFrames {
  Topology topology;
  bool skip_adjacent = false;
  std::vector<std::vector<vec3f>> vertices;
  std::vector<std::vector<PrimPair>> pairs;
  uint32_t num_frames() const { return uint32_t(vertices.size()); }
};

inline ExactFrames exact_frames(const FrameSource& source, bool skip_adjacent = false) {
  ExactFrames e{source.topology(), skip_adjacent, {}, {}};
  e.vertices.resize(source.num_frames());
  e.pairs.resize(source.num_frames());
  for (uint32_t f = 0; f < source.num_frames(); ++f) {
    source.frame(f, e.vertices[f]);
    e.pairs[f] = sweep_oracle_pairs(e.topology, e.vertices[f], skip_adjacent);
  }
  return e;
}

// Every pipeline (or those named in `only`), through the public factory, each given the
// topology; the O(N^2) brute pipeline joins only up to brute_limit triangles.
struct PipelineSet {
  std::vector<std::string> names;
  std::vector<std::unique_ptr<Pipeline>> pipelines;
};

inline PipelineSet make_pipelines(const PipelineConfig& base, const Topology& topo, size_t brute_limit,
                                  const std::vector<std::string>& only) {
  PipelineSet set;
  for (const auto& name : pipeline_names()) {
    if (name == oracle_pipeline() && topo.faces.size() > brute_limit) continue;
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
    PipelineConfig cfg = base;
    cfg.name = name;
    set.names.push_back(name);
    set.pipelines.push_back(make_pipeline(cfg));
    set.pipelines.back()->set_topology(topo);
  }
  return set;
}

// One frame through every pipeline of the set: exactly the expected pairs.
inline void expect_frame_exact(PipelineSet& set, uint32_t f, const std::vector<vec3f>& v,
                               const std::vector<PrimPair>& expected) {
  for (size_t p = 0; p < set.pipelines.size(); ++p) {
    const FrameStats s = set.pipelines[p]->run_frame(v);
    ASSERT_EQ(s.pairs, expected.size()) << set.names[p] << " frame " << f << " (" << s.op << ")";
    const PairSetDiff d = diff_pair_sets(expected, set.pipelines[p]->sorted_pairs());
    ASSERT_TRUE(d.equal()) << set.names[p] << " frame " << f << " (" << s.op << "): " << d.missing_count
                           << " missing, " << d.unexpected_count << " unexpected";
  }
}

// Every pipeline (or those named in `only`) on every frame of a scene, against the sweep
// oracle; with a pair buffer far too small at the start so it must grow. One frame at a
// time: the scene's frames are never all held.
inline void check_pipelines_on(const PipelineConfig& base, FrameSource& source,
                               size_t brute_limit = 100000, const std::vector<std::string>& only = {}) {
  const Topology& topo = source.topology();
  PipelineSet set = make_pipelines(base, topo, brute_limit, only);
  std::vector<vec3f> v;
  for (uint32_t f = 0; f < source.num_frames(); ++f) {
    source.frame(f, v);
    expect_frame_exact(set, f, v, sweep_oracle_pairs(topo, v, base.skip_adjacent));
    if (testing::Test::HasFatalFailure()) return;
  }
}

// The same over frames whose oracle pairs are already known.
inline void check_pipelines_on(const PipelineConfig& base, const ExactFrames& exact, size_t brute_limit = 100000,
                               const std::vector<std::string>& only = {}) {
  ASSERT_EQ(base.skip_adjacent, exact.skip_adjacent) << "the oracle's pairs were computed for other settings";
  PipelineSet set = make_pipelines(base, exact.topology, brute_limit, only);
  for (uint32_t f = 0; f < exact.num_frames(); ++f) {
    expect_frame_exact(set, f, exact.vertices[f], exact.pairs[f]);
    if (testing::Test::HasFatalFailure()) return;
  }
}

// A pipeline given its topology again (what `run --repeat` does between passes) starts
// over with the buffers its first pass grew, and must report the same pairs frame by frame.
inline void check_second_pass_matches_first(const PipelineConfig& base, FrameSource& source) {
  const Topology& topo = source.topology();
  std::vector<vec3f> v;
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = base;
    cfg.name = name;
    auto p = make_pipeline(cfg);
    std::vector<std::vector<PrimPair>> first;
    for (int pass = 0; pass < 2; ++pass) {
      p->set_topology(topo);
      for (uint32_t f = 0; f < source.num_frames(); ++f) {
        source.frame(f, v);
        const FrameStats s = p->run_frame(v);
        if (pass == 0) {
          first.push_back(p->sorted_pairs());
          continue;
        }
        ASSERT_EQ(s.pairs, first[f].size()) << name << " second pass, frame " << f << " (" << s.op << ")";
        ASSERT_TRUE(diff_pair_sets(first[f], p->sorted_pairs()).equal()) << name << " second pass, frame " << f;
      }
    }
  }
}

inline PipelineConfig config_for(const std::string& device, double pairs_per_triangle,
                                 double front_per_triangle = 8.0, uint32_t front_cycle = 4) {
  PipelineConfig c;
  c.device = device;
  c.capacity.pairs_per_triangle = pairs_per_triangle;
  c.capacity.front_per_triangle = front_per_triangle;
  c.fronts.cycle = front_cycle;
  // Maintenances in their frames, on the GPU as on the host, so that both run one plan
  // (check_rebuild_ahead runs the other ways).
  c.tree.maintain_ahead = AutoSwitch::off;
  return c;
}

// Scenes whose motion makes fronts sprout and prune: a rolling cloth, the funnel, and a
// soup whose jitter is larger than its triangles.
inline std::vector<std::string> front_scene_names() { return {"cloth_wave", "funnel", "soup"}; }

inline std::unique_ptr<FrameSource> front_scene(const std::string& name, uint32_t cloth_res, uint32_t frames) {
  if (name == "cloth_wave") return make_generator("cloth-wave", {{"res", cloth_res}, {"frames", frames}});
  if (name == "funnel")
    return make_generator("funnel", {{"res", cloth_res}, {"frames", frames}, {"segments", 16}, {"ball_level", 1}});
  return make_generator(
      "soup", {{"triangles", 3000}, {"distribution", "clustered"}, {"jitter", 3.0}, {"frames", frames}, {"seed", 5}});
}

inline std::string front_scene_name(const testing::TestParamInfo<std::string>& info) { return info.param; }

// Every pipeline exact on every frame of front scene `name` under the fixed cycles 1, 2, 3
// and 5 and under auto (0), on `device`.
inline void check_front_cycles(const std::string& device, const std::string& name, uint32_t cloth_res,
                               uint32_t frames) {
  const ExactFrames scene = exact_frames(*front_scene(name, cloth_res, frames));
  for (uint32_t cycle : {1u, 2u, 3u, 5u, 0u}) {
    SCOPED_TRACE("front cycle " + std::to_string(cycle));
    check_pipelines_on(config_for(device, 0.5, 0.05, cycle), scene);
    if (testing::Test::HasFatalFailure()) return;
  }
}

// Runs pipeline `p` (made from `cfg`) over every frame of a scene against the oracle's
// pairs; returns the frames' stats for the caller to check which operations ran.
inline std::vector<FrameStats> run_exact(Pipeline& p, const PipelineConfig& cfg, const ExactFrames& exact) {
  EXPECT_EQ(cfg.skip_adjacent, exact.skip_adjacent) << "the oracle's pairs were computed for other settings";
  p.set_topology(exact.topology);
  std::vector<FrameStats> out;
  for (uint32_t f = 0; f < exact.num_frames(); ++f) {
    out.push_back(p.run_frame(exact.vertices[f]));
    const FrameStats& s = out.back();
    const std::vector<PrimPair>& expected = exact.pairs[f];
    EXPECT_EQ(s.pairs, expected.size()) << cfg.name << " frame " << f << " (" << s.op << ")";
    const PairSetDiff d = diff_pair_sets(expected, p.sorted_pairs());
    EXPECT_TRUE(d.equal()) << cfg.name << " frame " << f << " (" << s.op << "): " << d.missing_count
                           << " missing, " << d.unexpected_count << " unexpected";
    if (!d.equal()) break;
  }
  return out;
}

inline std::vector<FrameStats> run_exact(const PipelineConfig& cfg, const ExactFrames& exact) {
  auto p = make_pipeline(cfg);
  return run_exact(*p, cfg, exact);
}

// A plan recorded from one run, replayed on a fresh pipeline (pipeline/plan_record.h): the
// same steps frame by frame, every frame exact. Pipeline c with Formula 2 forced to
// restructure (its replay restructures what its own inspection finds), and pipeline a's
// plan on pipeline b, whose own cycle would differ.
inline void check_replayed_plans(const std::string& device, const ExactFrames& scene) {
  for (const auto& [recorder, replayer] : {std::pair{"c", "c"}, std::pair{"a", "b"}}) {
    SCOPED_TRACE(std::string(recorder) + "'s plan on " + replayer);
    PipelineConfig cfg = config_for(device, 0.5, 0.05, 2);
    cfg.restructure.quality = 0.0;
    cfg.restructure.min_leaves = 4;
    cfg.restructure.threshold_refit = 0.0;
    cfg.restructure.threshold_build = 1.01;
    cfg.restructure.priced = false;  // every restructure Formula 2 asks for runs
    cfg.name = recorder;
    const std::vector<FrameStats> recorded = run_exact(cfg, scene);
    auto plan = std::make_shared<RecordedPlan>();
    plan->source = recorder;
    plan->records_probes = true;
    for (size_t k = 0; k < recorded.size(); ++k) {
      ASSERT_TRUE(recorded[k].plan.has_value()) << "frame " << k;
      plan->frames.push_back({uint32_t(k), *recorded[k].plan, 0});
    }
    if (cfg.name == std::string("c")) {
      ASSERT_EQ(plan_outline(*plan).find("restructure: —"), std::string::npos) << plan_outline(*plan);
    }
    cfg.name = replayer;
    cfg.fronts.cycle = 3;  // its own cycle, which the plan overrides
    auto p = make_pipeline(cfg);
    ASSERT_TRUE(p->replay_plan(plan));
    const std::vector<FrameStats> replayed = run_exact(*p, cfg, scene);
    ASSERT_EQ(replayed.size(), recorded.size());
    for (size_t k = 0; k < replayed.size(); ++k) {
      EXPECT_EQ(replayed[k].plan, recorded[k].plan) << "frame " << k;
      EXPECT_EQ(replayed[k].op, recorded[k].op) << "frame " << k;
    }
  }
}

// Pipeline c with Formula 2 forced into each branch by extreme settings: quality factor 0
// makes every subtree with fronts degraded; thresholds pick the branch. Every frame must
// stay exact and the forced decision must actually be taken.
inline void check_forced_decisions(const std::string& device, const ExactFrames& scene, uint32_t cycle,
                                   SplitRule split = SplitRule::rigid) {
  struct Forced {
    const char* decision;
    double refit, build;
    const char* op;  // what a frame with that decision runs
  };
  for (const Forced& f : {Forced{"restructure", 0.0, 1.01, "refit+restructure"},
                          Forced{"rebuild", 0.0, 0.0, "build+generate"},
                          Forced{"refit", 1.01, 1.01, nullptr}}) {
    PipelineConfig cfg = config_for(device, 0.5, 0.05, cycle);
    cfg.name = "c";
    cfg.tree.split = split;
    cfg.tree.rebuild_ahead = AutoSwitch::off;  // a rebuild in its frame (check_rebuild_ahead has the other)
    cfg.restructure.quality = 0.0;
    cfg.restructure.min_leaves = 4;
    cfg.restructure.threshold_refit = f.refit;
    cfg.restructure.threshold_build = f.build;
    // Forced means every time: no price declines a restructure (pipeline/restructure_price.h).
    cfg.restructure.priced = false;
    const auto frames = run_exact(cfg, scene);
    size_t taken = 0;
    for (const auto& s : frames) {
      EXPECT_TRUE(s.quality.decision.empty() || s.quality.decision == f.decision) << s.quality.decision;
      if (s.quality.decision != f.decision) continue;
      ++taken;
      if (f.op) {
        EXPECT_EQ(s.op, f.op);
      }
    }
    EXPECT_GT(taken, 0u) << "forced decision " << f.decision << " never taken (cycle " << cycle << ")";
  }
  // A quality factor nothing reaches: inspections find no candidate, nothing is decided.
  PipelineConfig cfg = config_for(device, 8.0, 8.0, cycle);
  cfg.name = "restructure";
  cfg.restructure.quality = 1e9;
  for (const auto& s : run_exact(cfg, scene)) {
    EXPECT_EQ(s.quality.candidates, 0u);
    EXPECT_TRUE(s.quality.decision.empty());
  }
}

// Rebuild steps of a recorded run: builds ahead and adoptions, each ahead adopted before
// the next and every front preserved while one runs (plan_record.cpp checks the rest).
struct AheadSteps {
  size_t aheads = 0, adopts = 0;
  size_t update_aheads = 0, update_adopts = 0;  // --update-ahead's
};
inline AheadSteps count_ahead_steps(const std::vector<FrameStats>& frames) {
  AheadSteps n;
  bool in_flight = false;
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_TRUE(frames[k].plan.has_value()) << "frame " << k;
    if (!frames[k].plan) continue;
    const PlanStep& s = *frames[k].plan;
    const bool launches = s.trees == TreeStep::ahead || s.trees == TreeStep::update_ahead;
    const bool adopts = s.trees == TreeStep::adopt || s.trees == TreeStep::adopt_update;
    if (launches) {
      EXPECT_FALSE(in_flight) << "frame " << k << ": " << tree_step_name(s.trees) << " while one runs";
      in_flight = true;
      ++(s.trees == TreeStep::ahead ? n.aheads : n.update_aheads);
    }
    if (adopts) {
      EXPECT_TRUE(in_flight) << "frame " << k << ": " << tree_step_name(s.trees) << " without side work";
      in_flight = false;
      ++(s.trees == TreeStep::adopt ? n.adopts : n.update_adopts);
    }
    EXPECT_FALSE(in_flight && s.trees == TreeStep::build) << "frame " << k << ": a build while one runs ahead";
    if (in_flight || adopts) {
      EXPECT_FALSE(s.runs(FrontOp::update) || s.runs(FrontOp::generate) || s.runs(FrontOp::restructure))
          << "frame " << k << ": " << format_plan_step(s);
    }
  }
  return n;
}

// --rebuild-ahead (pipeline/front_pipeline.h): rebuilds built on the side stream and adopted
// at a later frame. Every front pipeline that can build ahead, with rebuilds every second or
// third frame (--rebuild-every) or from Formula 2 (c, every subtree a candidate), front and
// pair buffers far too small (fronts built ahead outgrow theirs and are generated again at
// the adoption): every frame exact, builds ahead in the plan and adopted, and the recorded
// plan replayed on a fresh pipeline runs the same steps exactly; with --maintain-ahead on
// the front cycle's maintenances (every second frame) are the builds ahead, with auto they
// run both ways; with --update-ahead on the cycle's updates run on the side (with buffers
// this small an adopting frame may have to update them again); with --ahead-generate place
// the fronts built or updated ahead are produced twice, in order, into the arrays the
// current fronts lend. The reference
// strategy and the radix orderings build in their frames.
inline void check_rebuild_ahead(const std::string& device, const ExactFrames& scene) {
  struct Case {
    const char* pipeline;
    uint32_t rebuild_every;
    bool formula2;
    AutoSwitch maintain_ahead = AutoSwitch::off;
    AutoSwitch update_ahead = AutoSwitch::off;
    bool placed = false;  // --ahead-generate place
  };
  for (const Case& c : {Case{"a", 2, false}, Case{"b", 3, false}, Case{"c", 2, false}, Case{"unordered", 2, false},
                        Case{"periodic", 3, false}, Case{"c", 0, true}, Case{"b", 0, false, AutoSwitch::on},
                        Case{"c", 0, false, AutoSwitch::on}, Case{"b", 0, false, AutoSwitch::automatic},
                        Case{"c", 0, false, AutoSwitch::automatic},
                        Case{"a", 0, false, AutoSwitch::off, AutoSwitch::on},
                        Case{"b", 0, false, AutoSwitch::off, AutoSwitch::on},
                        Case{"c", 0, false, AutoSwitch::off, AutoSwitch::on},
                        Case{"unordered", 0, false, AutoSwitch::off, AutoSwitch::on},
                        Case{"periodic", 0, false, AutoSwitch::off, AutoSwitch::on},
                        Case{"b", 3, false, AutoSwitch::off, AutoSwitch::on},
                        Case{"a", 2, false, AutoSwitch::off, AutoSwitch::off, true},
                        Case{"b", 3, false, AutoSwitch::off, AutoSwitch::off, true},
                        Case{"c", 2, false, AutoSwitch::off, AutoSwitch::off, true},
                        Case{"unordered", 2, false, AutoSwitch::off, AutoSwitch::off, true},
                        Case{"periodic", 3, false, AutoSwitch::off, AutoSwitch::off, true},
                        Case{"c", 0, true, AutoSwitch::off, AutoSwitch::off, true},
                        Case{"c", 0, false, AutoSwitch::on, AutoSwitch::off, true},
                        Case{"b", 3, false, AutoSwitch::off, AutoSwitch::on, true},
                        Case{"a", 0, false, AutoSwitch::off, AutoSwitch::on, true},
                        Case{"c", 0, false, AutoSwitch::off, AutoSwitch::on, true},
                        Case{"unordered", 0, false, AutoSwitch::off, AutoSwitch::on, true},
                        Case{"periodic", 0, false, AutoSwitch::off, AutoSwitch::on, true}}) {
    SCOPED_TRACE(std::string(c.pipeline) + (c.formula2 ? ", Formula 2 rebuilds" : ", rebuild every ") +
                 (c.formula2 ? "" : std::to_string(c.rebuild_every)) + ", maintained ahead " +
                 auto_switch_name(c.maintain_ahead) + ", updated ahead " + auto_switch_name(c.update_ahead) +
                 (c.placed ? ", placed" : ""));
    PipelineConfig cfg = config_for(device, 0.5, 0.05, 2);
    cfg.name = c.pipeline;
    cfg.tree.rebuild_ahead = AutoSwitch::on;
    cfg.tree.rebuild_every = c.rebuild_every;
    cfg.tree.maintain_ahead = c.maintain_ahead;
    cfg.fronts.update_ahead = c.update_ahead;
    cfg.tree.ahead_placed = c.placed;
    if (c.formula2) {
      cfg.restructure.quality = 0.0;
      cfg.restructure.min_leaves = 4;
      cfg.restructure.threshold_refit = 0.0;
      cfg.restructure.threshold_build = 0.0;
    }
    const std::vector<FrameStats> recorded = run_exact(cfg, scene);
    if (testing::Test::HasFailure()) return;
    const AheadSteps n = count_ahead_steps(recorded);
    const bool updates_ahead = c.update_ahead == AutoSwitch::on;
    if (scene.topology.faces.size() > 1 && !c.formula2) {
      if (!updates_ahead || c.rebuild_every > 0) {
        EXPECT_GT(n.aheads, 0u);
      }
      if (updates_ahead) {
        EXPECT_GT(n.update_aheads, 0u);
      }
    }
    if (!updates_ahead) {
      EXPECT_EQ(n.update_aheads, 0u);
    }
    EXPECT_GE(n.adopts + 1, n.aheads);
    EXPECT_GE(n.update_adopts + 1, n.update_aheads);
    auto plan = std::make_shared<RecordedPlan>();
    plan->source = c.pipeline;
    plan->records_probes = true;
    for (size_t k = 0; k < recorded.size(); ++k) plan->frames.push_back({uint32_t(k), *recorded[k].plan, 0});
    auto p = make_pipeline(cfg);
    ASSERT_TRUE(p->replay_plan(plan));
    const std::vector<FrameStats> replayed = run_exact(*p, cfg, scene);
    ASSERT_EQ(replayed.size(), recorded.size());
    for (size_t k = 0; k < replayed.size(); ++k) EXPECT_EQ(replayed[k].plan, recorded[k].plan) << "frame " << k;
  }
  // A pass that ends with its build ahead in flight (the last frame rebuilds), then another
  // pass on the same pipeline, as the run loop's warm-up and repeats do: it starts clean,
  // exact from its first frame, the fronts generated ahead scattered or placed.
  if (scene.num_frames() >= 3) {
    ExactFrames odd = scene;
    const size_t frames = odd.num_frames() % 2 == 1 ? odd.num_frames() : odd.num_frames() - 1;
    odd.vertices.resize(frames);
    odd.pairs.resize(frames);
    for (bool placed : {false, true}) {
      SCOPED_TRACE(std::string("c, a pass after one ending in flight") + (placed ? ", placed" : ""));
      PipelineConfig cfg = config_for(device, 0.5, 0.05, 2);
      cfg.name = "c";
      cfg.tree.rebuild_ahead = AutoSwitch::on;
      cfg.tree.rebuild_every = 2;
      cfg.tree.ahead_placed = placed;
      auto p = make_pipeline(cfg);
      const std::vector<FrameStats> first = run_exact(*p, cfg, odd);
      if (scene.topology.faces.size() > 1) {
        ASSERT_TRUE(first.back().plan.has_value());
        EXPECT_EQ(first.back().plan->trees, TreeStep::ahead) << "the last frame builds ahead";
      }
      if (!testing::Test::HasFailure()) run_exact(*p, cfg, odd);
    }
  }
  for (const char* name : {"reference", "radix-order"}) {
    PipelineConfig cfg = config_for(device, 0.5, 0.05, 2);
    cfg.name = name;
    cfg.tree.rebuild_ahead = AutoSwitch::on;
    cfg.tree.rebuild_every = 2;
    EXPECT_EQ(count_ahead_steps(run_exact(cfg, scene)).aheads, 0u) << name;
  }
}

// Scenes for check_rebuild_ahead: the front scenes and the soups at the extremes (none, one
// and two triangles, identical centroids, duplicates, coordinates at 1e-20 and 1e20).
inline std::vector<std::string> rebuild_ahead_scene_names() {
  return {"cloth_wave", "funnel", "soup", "none", "one", "two", "identical", "duplicates", "tiny", "huge"};
}
inline ExactFrames rebuild_ahead_scene(const std::string& name, uint32_t cloth_res, uint32_t frames) {
  const auto soup = [&](uint64_t n, const char* dist, double scale, double dups) {
    return exact_frames(*make_generator("soup", {{"triangles", n},
                                                 {"distribution", dist},
                                                 {"scale", scale},
                                                 {"duplicates", dups},
                                                 {"jitter", 3.0},
                                                 {"frames", frames},
                                                 {"seed", 17 + n}}));
  };
  if (name == "none") return soup(0, "uniform", 1.0, 0.0);
  if (name == "one") return soup(1, "uniform", 1.0, 0.0);
  if (name == "two") return soup(2, "clustered", 1.0, 0.0);
  if (name == "identical") return soup(600, "identical", 1.0, 0.0);
  if (name == "duplicates") return soup(1000, "uniform", 1.0, 0.3);
  if (name == "tiny") return soup(1000, "clustered", 1e-20, 0.0);
  if (name == "huge") return soup(1000, "clustered", 1e20, 0.0);
  return exact_frames(*front_scene(name, cloth_res, frames));
}

// Restructures hand-picked subtrees of a refitted tree — all nodes of a given depth,
// including the leftmost (first leaf 0) and rightmost (escape past the end) ones — and
// checks the tree against the reference and the self query against the oracle.
template <class Exec>
void check_restructure_subtrees(FrameSource& source, uint32_t depth) {
  const Topology& topo = source.topology();
  Exec exec;
  Lbvh<Exec> bvh(exec);
  bvh.refit_levels = true;
  RestructureScratch<Exec> rs(exec);
  TestMesh<Exec> m(exec, topo);
  const MeshView mesh = m.view();
  std::vector<vec3f> v;
  const uint32_t n = uint32_t(topo.faces.size());
  rs.reserve(n, 2);
  for (uint32_t f = 0; f < source.num_frames(); ++f) {
    source.frame(f, v);
    m.upload(exec, v);
    if (f == 0) {
      build_hierarchy(exec, bvh, mesh, MortonBits::b63);
      order_depth_first(exec, bvh);
      continue;
    }
    refit(exec, bvh, mesh);
    HostBvh before = download(exec, bvh);
    // Nodes at `depth` (root 0) with at least two leaves, found by walking down.
    std::vector<uint32_t> level = {0}, picked;
    for (uint32_t d = 0; d < depth; ++d) {
      std::vector<uint32_t> next;
      for (uint32_t k : level)
        for (uint32_t c : {before.node_left[k], before.node_right[k]})
          if (!is_leaf(c)) next.push_back(c);
      level = next;
    }
    uint32_t leaves = 0;
    for (uint32_t k : level) {
      picked.push_back(k);
      leaves += before.node_last[k] - before.node_first[k] + 1;
    }
    ASSERT_FALSE(picked.empty());
    exec.copy_from_host(rs.node.data(), picked.data(), picked.size());
    describe_candidates(exec, bvh, rs, uint32_t(picked.size()));
    restructure_subtrees(exec, bvh, rs, uint32_t(picked.size()), leaves);
    HostBvh after = download(exec, bvh);
    after.count_log.clear();
    ASSERT_EQ(check_bvh(after, topo, v), "") << "frame " << f;
    expect_treelet_tiles(exec, bvh, after, "restructured, frame " + std::to_string(f));
    for (uint32_t k : picked) {
      EXPECT_EQ(after.node_first[k], before.node_first[k]);
      EXPECT_EQ(after.node_last[k], before.node_last[k]);
      EXPECT_EQ(after.node_escape[k], before.node_escape[k]);
      EXPECT_EQ(after.node_parent[k], before.node_parent[k]);
    }
    expect_self_query_exact(exec, bvh, topo, v, m.pairs, m.count, f);
    if (testing::Test::HasFatalFailure()) return;
    // The restructured tree's tiles, level tables and spanning nodes are indexed anew: every
    // refit agrees and keeps it valid.
    expect_refits_agree(exec, bvh, mesh, "restructured, frame " + std::to_string(f));
    HostBvh refitted = download(exec, bvh);
    refitted.count_log.clear();
    ASSERT_EQ(check_bvh(refitted, topo, v), "") << "refit after restructure, frame " << f;
  }
}

// With fewer shared-memory slots than spanning nodes (refit_top.h), the slots past them go
// through global memory: the refit must still agree with the hand-over between blocks, keep
// the tree valid and the query exact, frame after frame.
template <class Exec>
void check_refit_top_spill() {
  check_soup_case<Exec>({kRefitTopMaxLeaves, "clustered", 1.0, 0.0, MortonBits::b63}, 16);
}

// A tree past the default size with its top in one block anyway (--refit-top-leaves):
// hundreds of spanning nodes, every one in shared memory.
template <class Exec>
void check_refit_top_large_tree() {
  check_soup_case<Exec>({100000, "clustered", 1.0, 0.0, MortonBits::b63}, kRefitTopSharedSlots, kRefitTopLeavesLimit);
}

// A refit handed counters to zero (CounterReset, the steady frame's pair counters) zeroes
// every one of them and gives the boxes of a refit without; a tree with fewer leaves than
// counters leaves them alone and says so, so that the caller zeroes them itself.
template <class Exec>
void check_refit_counter_reset() {
  constexpr uint32_t kCount = 12;
  const std::vector<unsigned long long> poison(kCount, 0xdeadbeefull);
  for (bool levels : {false, true})
  for (uint64_t triangles : {3ull, 12ull, 1000ull, 20000ull}) {
    SCOPED_TRACE("triangles " + std::to_string(triangles) + (levels ? ", level refit" : ", climbing refit"));
    auto source = soup_source({triangles, "clustered", 1.0, 0.0, MortonBits::b63});
    const Topology& topo = source->topology();
    Exec exec;
    Lbvh<Exec> bvh(exec);
    bvh.refit_levels = levels;
    TestMesh<Exec> m(exec, topo);
    Array<unsigned long long> counters(exec.memory(), "test.counters");
    counters.reserve(kCount);
    std::vector<vec3f> v;
    source->frame(0, v);
    m.upload(exec, v);
    const MeshView mesh = m.view();
    build_hierarchy(exec, bvh, mesh, MortonBits::b63);
    order_depth_first(exec, bvh);
    source->frame(1, v);
    m.upload(exec, v);
    EXPECT_FALSE(refit(exec, bvh, mesh));
    const HostBvh plain = download(exec, bvh);
    exec.copy_from_host(counters.data(), poison.data(), kCount);
    const bool zeroed = refit(exec, bvh, mesh, CounterReset{counters.data(), kCount});
    std::vector<unsigned long long> after(kCount);
    exec.copy_to_host(after.data(), counters.data(), kCount);
    EXPECT_EQ(zeroed, triangles >= kCount);
    EXPECT_EQ(after, zeroed ? std::vector<unsigned long long>(kCount, 0ull) : poison);
    EXPECT_TRUE(same_boxes(download(exec, bvh), plain)) << "boxes differ with the counters zeroed on the way";
  }
}

// A piece ordered build (--build-pieces) over `source`'s first frame, with the pieces
// mesh_pieces finds: a valid tree whose every piece's leaves are contiguous and span one
// subtree (an internal node, or the leaf of a one-face piece, covering exactly them), and a
// self query that reports exactly the oracle's pairs, before and after a refit to the last
// frame. Returns the pieces.
template <class Exec>
uint32_t check_piece_order(const FrameSource& source, MortonBits bits) {
  const Topology& topo = source.topology();
  Exec exec;
  Lbvh<Exec> bvh(exec);
  TestMesh<Exec> m(exec, topo);
  const MeshPieces pieces = mesh_pieces(topo.faces, topo.num_vertices, {});
  Array<uint32_t> leaf_piece(exec.memory(), "test.leaf_piece"), piece_first(exec.memory(), "test.piece_first");
  leaf_piece.reserve(pieces.leaf_piece.size());
  piece_first.reserve(pieces.piece_first.size());
  exec.copy_from_host(leaf_piece.data(), pieces.leaf_piece.data(), pieces.leaf_piece.size());
  exec.copy_from_host(piece_first.data(), pieces.piece_first.data(), pieces.piece_first.size());
  const PieceOrder order{leaf_piece.data(), piece_first.data(), piece_bits(pieces.count())};
  EXPECT_TRUE(piece_order_fits(bits, order.piece_bits)) << pieces.count() << " pieces";
  std::vector<vec3f> v;
  source.frame(0, v);
  m.upload(exec, v);
  const MeshView mesh = m.view();
  build_hierarchy(exec, bvh, mesh, bits, FaceSubset{nullptr, mesh.num_faces}, nullptr, order);
  order_depth_first(exec, bvh);
  const HostBvh h = download(exec, bvh);
  EXPECT_EQ(check_bvh(h, topo, v), "");
  // Each piece's leaves: the range [first, last] of leaf positions, which must hold
  // nothing else, and a node spanning exactly it.
  const uint32_t n = uint32_t(h.leaf_prim.size());
  std::vector<uint32_t> first(pieces.count(), n), last(pieces.count(), 0), size(pieces.count(), 0);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t p = pieces.leaf_piece[h.leaf_prim[k]];
    first[p] = std::min(first[p], k);
    last[p] = std::max(last[p], k);
    ++size[p];
  }
  std::vector<bool> spanned(pieces.count(), false);
  for (uint32_t p = 0; p < pieces.count(); ++p) spanned[p] = size[p] == 1;
  for (size_t j = 0; j < h.node_first.size(); ++j) {
    const uint32_t p = pieces.leaf_piece[h.leaf_prim[h.node_first[j]]];
    if (h.node_first[j] == first[p] && h.node_last[j] == last[p]) spanned[p] = true;
  }
  for (uint32_t p = 0; p < pieces.count(); ++p) {
    EXPECT_EQ(last[p] - first[p] + 1, size[p]) << "piece " << p << " is not contiguous";
    EXPECT_TRUE(spanned[p]) << "no subtree spans piece " << p;
    if (testing::Test::HasFailure()) break;
  }
  expect_self_query_exact(exec, bvh, topo, v, m.pairs, m.count, 0);
  source.frame(source.num_frames() - 1, v);
  m.upload(exec, v);
  refit(exec, bvh, mesh);
  expect_self_query_exact(exec, bvh, topo, v, m.pairs, m.count, source.num_frames() - 1);
  return pieces.count();
}

// The radix-sort ordering of the BVH gives the histogram ordering's tree, node for node.
template <class Exec>
void check_radix_order_matches(const SoupCase& c) {
  auto source = soup_source(c);
  const Topology& topo = source->topology();
  Exec exec;
  Lbvh<Exec> bvh(exec);
  TestMesh<Exec> m(exec, topo);
  std::vector<vec3f> v;
  source->frame(0, v);
  m.upload(exec, v);
  const MeshView mesh = m.view();
  build_hierarchy(exec, bvh, mesh, c.bits);
  order_depth_first(exec, bvh);
  HostBvh histogram = download(exec, bvh);
  build_hierarchy(exec, bvh, mesh, c.bits);
  order_depth_first_radix(exec, bvh);
  HostBvh radix = download(exec, bvh);
  radix.count_log = histogram.count_log = {};
  radix.offset_log = histogram.offset_log = {};
  ASSERT_EQ(check_bvh(radix, topo, v), "");
  EXPECT_EQ(radix.node_left, histogram.node_left);
  EXPECT_EQ(radix.node_right, histogram.node_right);
  EXPECT_EQ(radix.node_parent, histogram.node_parent);
  EXPECT_EQ(radix.node_escape, histogram.node_escape);
  EXPECT_EQ(radix.node_first, histogram.node_first);
  EXPECT_EQ(radix.leaf_parent, histogram.leaf_parent);
  EXPECT_EQ(radix.leaf_escape, histogram.leaf_escape);
}

// Co-vertex filtering: every pipeline drops exactly the overlapping pairs that share a
// vertex. The filtered oracle is checked against the unfiltered one first, so the test
// cannot pass with a filter that does nothing or drops too much.
inline void check_skip_adjacent(const std::string& device, FrameSource& source) {
  const Topology& topo = source.topology();
  std::vector<vec3f> v;
  source.frame(source.num_frames() - 1, v);
  const auto all = sweep_oracle_pairs(topo, v);
  const auto kept = sweep_oracle_pairs(topo, v, true);
  ASSERT_LT(kept.size(), all.size());
  ASSERT_GT(kept.size(), 0u);
  const PairSetDiff d = diff_pair_sets(all, kept);
  ASSERT_EQ(d.unexpected_count, 0u);
  for (const PrimPair& p : d.missing) {
    const Tri a = topo.faces[p.a], b = topo.faces[p.b];
    const std::set<uint32_t> va = {a.v0, a.v1, a.v2};
    EXPECT_TRUE(va.count(b.v0) || va.count(b.v1) || va.count(b.v2)) << p.a << " " << p.b;
  }
  PipelineConfig cfg = config_for(device, 0.5, 0.05, 2);
  cfg.skip_adjacent = true;
  check_pipelines_on(cfg, source);
}

// Declared queries (self of the cloth, inter of the cloth with the rigid bodies): the
// filtered oracle keeps exactly the pairs with a cloth face, and every pipeline matches it.
inline void check_declared_queries(const std::string& device, FrameSource& source) {
  const Topology& topo = source.topology();
  ASSERT_TRUE(topo.queries.declared);
  std::vector<vec3f> v;
  source.frame(source.num_frames() - 1, v);
  Topology everything = topo;
  everything.queries = {};
  const auto all = sweep_oracle_pairs(everything, v);
  const auto asked = sweep_oracle_pairs(topo, v);
  ASSERT_GT(asked.size(), 0u);
  ASSERT_LT(asked.size(), all.size());
  const uint32_t cloth_faces = topo.objects.at(0).num_faces;
  const PairSetDiff d = diff_pair_sets(all, asked);
  ASSERT_EQ(d.unexpected_count, 0u);
  for (const PrimPair& p : d.missing) EXPECT_TRUE(p.a >= cloth_faces && p.b >= cloth_faces) << p.a << " " << p.b;
  for (const PrimPair& p : asked) EXPECT_TRUE(p.a < cloth_faces || p.b < cloth_faces) << p.a << " " << p.b;
  check_pipelines_on(config_for(device, 0.5, 0.05, 2), source);
}

}  // namespace cdb::test
