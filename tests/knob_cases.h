#pragma once
// The speed/accuracy knobs (docs/design.md "Speed/accuracy knobs") through every pipeline,
// against a plain O(N^2) reference over boxes computed here independently of face_box:
// fat boxes (--box-margin), swept boxes (--boxes swept) and lazy refits (--refit-every).
// test_knobs_host.cpp runs them on the host executor, test_bvh_cuda.cu on CUDA.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cfenv>
#include <random>
#include <string>
#include <variant>
#include <vector>

#include "cdbench/oracle/sweep_oracle.h"
#include "bvh_cases.h"
#include "cdbench/core/outward_rounding.h"
#include "cdbench/core/pair_set.h"
#include "scenes/generators/generators.h"
#include "cdbench/geometry/objects.h"
#include "cdbench/pipeline/pipeline.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

// a - b and a + b rounded by the FPU in its directed rounding modes: the reference for the
// outward rounding face_box does in round-to-nearest arithmetic (core/outward_rounding.h).
// volatile keeps the operations between the mode switches.
inline float fpu_sub_down(float a, float b) {
  volatile float x = a, y = b;
  const int mode = std::fegetround();
  std::fesetround(FE_DOWNWARD);
  volatile float r = x - y;
  std::fesetround(mode);
  return r;
}

inline float fpu_add_up(float a, float b) {
  volatile float x = a, y = b;
  const int mode = std::fegetround();
  std::fesetround(FE_UPWARD);
  volatile float r = x + y;
  std::fesetround(mode);
  return r;
}

// Random (a, b >= 0) over every float exponent, subnormals included, half of them with b
// near a's magnitude, where every rounding case occurs; the one-ulp ties first.
inline void random_margin_operands(size_t n, std::vector<float>& a, std::vector<float>& b) {
  a = {1.0f, 1.0f, 1.0f + 0x1p-23f, 0.0f, 1e30f, -1e30f, std::numeric_limits<float>::max()};
  b = {0x1p-25f, 0x1p-24f, 0x1p-24f, 0x1p-149f, 1e-30f, 1e-30f, 1.0f};
  std::mt19937 rng(3);
  std::uniform_int_distribution<uint32_t> bits(0, 0x7F7FFFFFu);  // finite, >= 0
  while (a.size() < n) {
    const float x = std::bit_cast<float>(bits(rng));
    a.push_back(rng() & 1 ? -x : x);
    b.push_back(a.size() % 2 ? std::bit_cast<float>(bits(rng)) : x * std::ldexp(1.0f, -int(rng() % 30)));
  }
}

struct OutwardRoundingFn {
  const float* a;
  const float* b;
  float* down;
  float* up;
  CDB_HD void operator()(uint32_t i) const {
    down[i] = sub_round_down(a[i], b[i]);
    up[i] = add_round_up(a[i], b[i]);
  }
};

// The margin's outward rounding on the executor gives the host's bits (on CUDA: no FMA, no
// flushed subnormals).
template <class Exec>
void check_outward_rounding_on_executor(size_t n) {
  std::vector<float> a, b;
  random_margin_operands(n, a, b);
  Exec exec;
  Array<float> da, db, down, up;
  da.bind(exec.memory(), "test.a");
  db.bind(exec.memory(), "test.b");
  down.bind(exec.memory(), "test.down");
  up.bind(exec.memory(), "test.up");
  for (Array<float>* x : {&da, &db, &down, &up}) x->reserve(n);
  exec.copy_from_host(da.data(), a.data(), n);
  exec.copy_from_host(db.data(), b.data(), n);
  exec.for_each_n(n, OutwardRoundingFn{da.data(), db.data(), down.data(), up.data()});
  std::vector<float> got_down(n), got_up(n);
  exec.copy_to_host(got_down.data(), down.data(), n);
  exec.copy_to_host(got_up.data(), up.data(), n);
  for (size_t i = 0; i < n; ++i) {
    ASSERT_EQ(std::bit_cast<uint32_t>(got_down[i]), std::bit_cast<uint32_t>(sub_round_down(a[i], b[i])))
        << a[i] << " - " << b[i];
    ASSERT_EQ(std::bit_cast<uint32_t>(got_up[i]), std::bit_cast<uint32_t>(add_round_up(a[i], b[i])))
        << a[i] << " + " << b[i];
  }
}

// One face's box as the reference computes it: the triangle at `v`, grown by the
// triangle at `prev` when given, then by `margin` on each side, rounded outward.
inline void reference_box(const Tri& t, const std::vector<vec3f>& v, const std::vector<vec3f>* prev, float margin,
                          vec4f& lo, vec4f& hi) {
  const vec3f* pts[6] = {&v[t.v0], &v[t.v1], &v[t.v2], nullptr, nullptr, nullptr};
  int count = 3;
  if (prev) {
    pts[3] = &(*prev)[t.v0];
    pts[4] = &(*prev)[t.v1];
    pts[5] = &(*prev)[t.v2];
    count = 6;
  }
  lo = {pts[0]->x, pts[0]->y, pts[0]->z, 0};
  hi = lo;
  for (int k = 1; k < count; ++k) {
    lo = {std::min(lo.x, pts[k]->x), std::min(lo.y, pts[k]->y), std::min(lo.z, pts[k]->z), 0};
    hi = {std::max(hi.x, pts[k]->x), std::max(hi.y, pts[k]->y), std::max(hi.z, pts[k]->z), 0};
  }
  lo = {fpu_sub_down(lo.x, margin), fpu_sub_down(lo.y, margin), fpu_sub_down(lo.z, margin), 0};
  hi = {fpu_add_up(hi.x, margin), fpu_add_up(hi.y, margin), fpu_add_up(hi.z, margin), 0};
}

// Every overlapping pair of the given boxes (closed bounds), sorted by pair_key.
inline std::vector<PrimPair> brute_pairs(const std::vector<vec4f>& lo, const std::vector<vec4f>& hi) {
  std::vector<PrimPair> out;
  const uint32_t n = uint32_t(lo.size());
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = i + 1; j < n; ++j)
      if (lo[i].x <= hi[j].x && lo[j].x <= hi[i].x && lo[i].y <= hi[j].y && lo[j].y <= hi[i].y &&
          lo[i].z <= hi[j].z && lo[j].z <= hi[i].z)
        out.push_back({i, j});
  return out;
}

inline std::vector<PrimPair> reference_pairs(const Topology& topo, const std::vector<vec3f>& v,
                                             const std::vector<vec3f>* prev, float margin) {
  const size_t n = topo.faces.size();
  std::vector<vec4f> lo(n), hi(n);
  for (size_t f = 0; f < n; ++f) reference_box(topo.faces[f], v, prev, margin, lo[f], hi[f]);
  std::vector<PrimPair> pairs = brute_pairs(lo, hi);
  if (!topo.queries.declared) return pairs;
  // Declared queries: only the pairs the scene asks for, as every pipeline reports them.
  const PairFilterTables t = pair_filter_tables(topo.objects, topo.queries, n);
  std::erase_if(pairs, [&](PrimPair p) { return !pair_wanted(t.face_object.data(), t.partners.data(), p.a, p.b); });
  return pairs;
}

// Every pair of `expected` is in `actual` (both sorted by pair_key).
inline bool contains_all(const std::vector<PrimPair>& actual, const std::vector<PrimPair>& expected) {
  const auto less = [](PrimPair a, PrimPair b) { return pair_key(a) < pair_key(b); };
  return std::includes(actual.begin(), actual.end(), expected.begin(), expected.end(), less);
}

// A soup whose jitter is larger than its triangles: fast motion, pairs change every frame.
inline std::unique_ptr<FrameSource> fast_soup(uint32_t frames) {
  return make_generator("soup", {{"triangles", 1200}, {"distribution", "clustered"}, {"jitter", 3.0},
                                 {"frames", frames}, {"seed", 11}});
}

inline std::unique_ptr<FrameSource> rolling_cloth(uint32_t frames) {
  return make_generator("cloth-wave", {{"res", 16}, {"frames", frames}});
}

// Mean edge of the first frame's triangle boxes: margins are chosen relative to it.
inline float mean_box_extent(FrameSource& source) {
  std::vector<vec3f> v;
  source.frame(0, v);
  double sum = 0;
  for (const Tri& t : source.topology().faces) {
    vec4f lo, hi;
    reference_box(t, v, nullptr, 0.0f, lo, hi);
    sum += (hi.x - lo.x + hi.y - lo.y + hi.z - lo.z) / 3.0;
  }
  return float(sum / double(source.topology().faces.size()));
}

// Pipelines whose hierarchy --refit-every leaves stale (every tree pipeline but the
// per-frame rebuild); the baselines ignore the knob.
inline bool keeps_stale_boxes(const std::string& name) {
  return !(name == "sweep" || name == "hash" || name == "grid" || name == "brute" || name == "reference" ||
           name == "example-sap");
}

// A pipeline on `device` whose pair buffer starts too small, so that it must grow.
inline PipelineConfig growing_config(const std::string& device, const std::string& name) {
  PipelineConfig cfg;
  cfg.device = device;
  cfg.name = name;
  cfg.capacity.pairs_per_triangle = 0.5;
  return cfg;
}

// --dependent-launch (kernels scheduled while their predecessors run, waiting for them on
// the device), --preserve-warp and --preserve-bound (on with dependent launches, off
// without) and --phase-timing off, each with the refit level by level and climbing
// (--refit-levels), the first with two front nodes a preserve thread
// (--preserve-two-nodes), the second with one: every pipeline reports exactly the oracle's pairs, every frame, with and
// without frame graphs; with phases off no phase but the upload has a time and the frame
// has one.
inline void check_launch_knobs(const std::string& device, bool graph, bool dependent) {
  const ExactFrames funnel =
      exact_frames(*make_generator("funnel", {{"res", 40}, {"frames", 10}, {"segments", 16}, {"ball_level", 1}}));
  for (bool levels : {true, false})
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = growing_config(device, name);
    cfg.tree.refit_levels = levels ? AutoSwitch::on : AutoSwitch::off;
    cfg.fronts.cycle = 4;
    cfg.launch.cuda_graph = graph;
    cfg.launch.dependent_launch = dependent;
    cfg.fronts.preserve_warp = dependent ? AutoSwitch::on : AutoSwitch::off;
    cfg.fronts.preserve_bound = dependent ? AutoSwitch::on : AutoSwitch::off;
    cfg.fronts.preserve_two_nodes = levels ? AutoSwitch::on : AutoSwitch::off;
    cfg.launch.phase_timing = false;
    auto p = make_pipeline(cfg);
    p->set_topology(funnel.topology);
    for (uint32_t f = 0; f < funnel.num_frames(); ++f) {
      const FrameStats s = p->run_frame(funnel.vertices[f]);
      const std::string where = name + (graph ? " graph" : "") + (dependent ? " dependent" : "") +
                                (levels ? " two nodes a preserve thread" : " climbing refit") + " frame " +
                                std::to_string(f);
      EXPECT_GT(s.timing.total_ms, 0.0) << where;
      EXPECT_GT(s.timing.phase_ms[size_t(Phase::upload)], 0.0) << where;
      for (size_t ph = 0; ph < kPhaseCount; ++ph) {
        if (Phase(ph) == Phase::upload) continue;
        EXPECT_EQ(s.timing.phase_ms[ph], 0.0) << where << ", phase " << ph;
      }
      const PairSetDiff d = diff_pair_sets(funnel.pairs[f], p->sorted_pairs());
      ASSERT_TRUE(d.equal()) << where << ": " << d.missing_count << " missing, " << d.unexpected_count << " extra";
    }
  }
}

// --build-pieces on and off: every pipeline reports exactly the oracle's pairs every frame on
// scenes of many pieces (falling spheres and cones; a soup, every triangle its own piece),
// with fronts maintained every 3 frames and a rebuild every 4 (bvh).
inline void check_build_pieces(const std::string& device) {
  const ExactFrames bodies = exact_frames(*make_generator(
      "n-body", {{"spheres", 24}, {"cones", 2}, {"sphere_level", 1}, {"frames", 8}, {"warmup", 0}, {"speed", 3.0}}));
  const ExactFrames soup = exact_frames(*fast_soup(6));
  for (const ExactFrames* scene : {&bodies, &soup})
    for (AutoSwitch pieces : {AutoSwitch::on, AutoSwitch::off})
      for (const auto& name : pipeline_names()) {
        PipelineConfig cfg = growing_config(device, name);
        cfg.tree.build_pieces = pieces;
        cfg.tree.rebuild_every = 4;
        cfg.fronts.cycle = 3;
        auto p = make_pipeline(cfg);
        p->set_topology(scene->topology);
        for (uint32_t f = 0; f < scene->num_frames(); ++f) {
          p->run_frame(scene->vertices[f]);
          const PairSetDiff d = diff_pair_sets(scene->pairs[f], p->sorted_pairs());
          ASSERT_TRUE(d.equal()) << name << (scene == &soup ? " soup" : " bodies") << " pieces "
                                 << auto_switch_name(pieces) << " frame " << f << ": " << d.missing_count
                                 << " missing, " << d.unexpected_count << " extra";
        }
      }
}

// How an update's front is kept: --order-updates, --update-warp, --update-in-place and
// --compact-share.
struct UpdateKnobs {
  bool order;
  AutoSwitch warp;
  bool in_place;
  double compact_share;
  std::string name() const {
    return std::string(order ? "sorted" : "kept") + " warp " + auto_switch_name(warp) +
           (in_place ? " in place, compact at " + std::to_string(compact_share) : " whole");
  }
};

// --order-updates off (updates keep their output in the order produced), --update-warp on
// and off (sprouts shared out in warps, on CUDA) and --update-in-place (updates write into
// the current front; compacted at once, now and then, or never), on every front pipeline
// with fixed cycles and auto (with --regenerate on: maintenances may generate), and fronts
// and pairs that start too small: exactly the oracle's pairs every frame, and under a fixed
// cycle fronts of the same sizes as the paper's sorted whole updates (the same nodes in
// another order).
inline void check_update_knobs(const std::string& device) {
  const ExactFrames funnel =
      exact_frames(*make_generator("funnel", {{"res", 40}, {"frames", 12}, {"segments", 16}, {"ball_level", 1}}));
  const ExactFrames soup = exact_frames(*fast_soup(8));
  const std::vector<UpdateKnobs> variants = {
      {true, AutoSwitch::off, false, 0.5},  {false, AutoSwitch::off, false, 0.5}, {false, AutoSwitch::on, false, 0.5},
      {true, AutoSwitch::off, true, 0.0},   {true, AutoSwitch::off, true, 0.3},   {true, AutoSwitch::on, true, 1e9},
      {false, AutoSwitch::on, true, 0.3}};
  for (const ExactFrames* scene : {&funnel, &soup})
    for (const auto& name : pipeline_names()) {
      const PipelineKind* kind = find_pipeline_kind(name);
      if (!std::holds_alternative<FrontStrategy>(kind->builds)) continue;
      for (uint32_t cycle : {1u, 3u, 0u}) {
        std::vector<std::array<uint64_t, 2>> sorted_sizes;
        uint32_t in_place_frames = 0;
        for (const UpdateKnobs& knobs : variants) {
          PipelineConfig cfg = growing_config(device, name);
          cfg.capacity.front_per_triangle = 0.5;
          cfg.fronts.cycle = cycle;
          cfg.fronts.order_updates = knobs.order;
          cfg.fronts.update_warp = knobs.warp;
          cfg.fronts.update_in_place = knobs.in_place;
          cfg.fronts.compact_share = knobs.compact_share;
          cfg.fronts.regenerate = cycle == 0;  // adaptive maintenances may generate where measured cheaper
          // Every variant runs one plan: maintenances in their frames (auto picks a way by times).
          cfg.tree.maintain_ahead = AutoSwitch::off;
          auto p = make_pipeline(cfg);
          p->set_topology(scene->topology);
          for (uint32_t f = 0; f < scene->num_frames(); ++f) {
            const FrameStats s = p->run_frame(scene->vertices[f]);
            const std::string where =
                name + " cycle " + std::to_string(cycle) + " " + knobs.name() + " frame " + std::to_string(f);
            const PairSetDiff d = diff_pair_sets(scene->pairs[f], p->sorted_pairs());
            ASSERT_TRUE(d.equal()) << where << ": " << d.missing_count << " missing, " << d.unexpected_count
                                   << " extra";
            if (s.op.find("+update-in-place") != std::string::npos) ++in_place_frames;
            if (cycle == 0 || (name == "c" && knobs.in_place)) continue;
            if (sorted_sizes.size() <= f)
              sorted_sizes.push_back({s.fronts.internal, s.fronts.external});
            else
              EXPECT_EQ(sorted_sizes[f], (std::array<uint64_t, 2>{s.fronts.internal, s.fronts.external})) << where;
          }
        }
        if (cycle == 1 && name != "reference") {
          EXPECT_GT(in_place_frames, 0u) << name << ": no update ran in place";
        }
      }
    }
}

// --update-probe: a probing preserve (the frame before an update, --front-cycle 2) sizes the
// front buffers for the update, which, run on the same geometry as the probe (each frame
// but the first given twice), then never grows them and runs once; without the probe the
// same updates outgrow their buffers (fronts and pairs start small, pairs with room to
// spare so that only fronts grow). Exact either way.
inline void check_update_probe(const std::string& device) {
  const ExactFrames soup = exact_frames(*fast_soup(6));
  for (const auto& name : {"a", "b", "c", "unordered", "periodic"})
    for (bool in_place : {true, false}) {
      uint32_t reruns_unprobed = 0;
      for (bool probe : {true, false}) {
        PipelineConfig cfg;
        cfg.device = device;
        cfg.name = name;
        cfg.capacity.pairs_per_triangle = 64;
        cfg.capacity.front_per_triangle = 0.25;
        cfg.fronts.cycle = 2;
        cfg.tree.maintain_ahead = AutoSwitch::off;  // every maintenance an update, on the GPU too
        cfg.fronts.update_probe = probe;
        cfg.fronts.update_in_place = in_place;
        auto p = make_pipeline(cfg);
        p->set_topology(soup.topology);
        for (uint32_t k = 0; k < 2 * soup.num_frames() - 1; ++k) {
          const uint32_t f = (k + 1) / 2;
          const FrameStats s = p->run_frame(soup.vertices[f]);
          const std::string where = std::string(name) + (in_place ? " in place" : " whole") +
                                    (probe ? " probed" : " unprobed") + " frame " + std::to_string(k);
          const PairSetDiff d = diff_pair_sets(soup.pairs[f], p->sorted_pairs());
          ASSERT_TRUE(d.equal()) << where << ": " << d.missing_count << " missing, " << d.unexpected_count << " extra";
          if (s.op.find("+update") == std::string::npos) continue;
          if (probe)
            EXPECT_EQ(s.timing.query_reruns, 0u) << where;
          else
            reruns_unprobed += s.timing.query_reruns;
        }
      }
      EXPECT_GT(reruns_unprobed, 0u) << name << (in_place ? " in place" : " whole")
                                     << ": the scene does not make unprobed updates grow their fronts";
    }
}

// A probing preserve's count (FrontSizes::update_yield) is what the host counts on the same
// fronts, with traversals shared in warps or not, on scenes with many pairs a front node
// (their preserve stages its pairs and counts per block) and few (it appends and counts per
// warp); and it bounds the fronts the update after it makes on the same geometry (each
// frame but the first given twice, --front-cycle 2). Every frame exact on both.
inline void check_probe_counts(const std::string& device) {
  for (const auto& scene : {"soup", "cloth_wave", "funnel"}) {
    const ExactFrames frames = exact_frames(*front_scene(scene, 24, 5));
    for (AutoSwitch warp : {AutoSwitch::on, AutoSwitch::off}) {
      std::vector<std::vector<FrameStats>> runs;
      for (const std::string& on : {device, std::string("cpu")}) {
        PipelineConfig cfg = config_for(on, 0.5, 0.05, 2);
        cfg.name = "a";
        cfg.fronts.preserve_warp = warp;
        cfg.fronts.preserve_bound = warp;  // both kernels of each kind, shared in warps or not
        auto p = make_pipeline(cfg);
        p->set_topology(frames.topology);
        runs.emplace_back();
        for (uint32_t k = 0; k < 2 * frames.num_frames() - 1; ++k) {
          const uint32_t f = (k + 1) / 2;
          runs.back().push_back(p->run_frame(frames.vertices[f]));
          const PairSetDiff d = diff_pair_sets(frames.pairs[f], p->sorted_pairs());
          ASSERT_TRUE(d.equal()) << scene << " on " << on << " frame " << k << ": " << d.missing_count << " missing, "
                                 << d.unexpected_count << " extra";
        }
      }
      uint32_t probes = 0;
      for (size_t k = 0; k < runs[0].size(); ++k) {
        const FrameStats &s = runs[0][k], &host = runs[1][k];
        const std::string where = std::string(scene) + (warp == AutoSwitch::on ? " in warps" : " alone") + " frame " +
                                  std::to_string(k) + " (" + s.op + ")";
        EXPECT_EQ(s.fronts.update_yield, host.fronts.update_yield) << where;
        if (s.fronts.update_yield == 0) continue;
        ++probes;
        ASSERT_LT(k + 1, runs[0].size()) << where << ": a probe on the last frame";
        const FrameStats& next = runs[0][k + 1];
        ASSERT_NE(next.op.find("+update"), std::string::npos) << where << ": no update after the probe";
        EXPECT_LE(next.fronts.internal + next.fronts.external + next.fronts.inter + next.fronts.rigid,
                  s.fronts.update_yield)
            << where << ": the update made more front nodes than the probe counted";
      }
      EXPECT_GT(probes, 0u) << scene;
    }
  }
}

// The pair buffer grows between frames once a frame's pairs fill seven eighths of it: a
// soup drawn together a little more each frame (its pairs grow 3-8% a frame, past twice the
// first frame's) overflows it only on the first frame, for every pipeline, and stays exact.
inline void check_pairs_grown_ahead(const std::string& device) {
  auto soup = fast_soup(1);
  std::vector<vec3f> v0;
  soup->frame(0, v0);
  double cx = 0, cy = 0, cz = 0;
  for (const vec3f& p : v0) cx += p.x, cy += p.y, cz += p.z;
  const float n = float(v0.size()), mx = float(cx) / n, my = float(cy) / n, mz = float(cz) / n;
  std::vector<std::vector<vec3f>> frames;
  std::vector<std::vector<PrimPair>> pairs;
  for (int f = 0; f < 16; ++f) {
    const float s = 1.0f - 0.02f * float(f);
    // Each triangle moves towards the centre whole: its shape stays, the gaps shrink.
    std::vector<vec3f> v = v0;
    for (const Tri& t : soup->topology().faces) {
      const vec3f a = v0[t.v0], b = v0[t.v1], d = v0[t.v2];
      const float gx = (a.x + b.x + d.x) / 3, gy = (a.y + b.y + d.y) / 3, gz = (a.z + b.z + d.z) / 3;
      const vec3f shift{(gx - mx) * (s - 1), (gy - my) * (s - 1), (gz - mz) * (s - 1)};
      for (uint32_t k : {t.v0, t.v1, t.v2}) v[k] = {v0[k].x + shift.x, v0[k].y + shift.y, v0[k].z + shift.z};
    }
    pairs.push_back(sweep_oracle_pairs(soup->topology(), v, false));
    frames.push_back(std::move(v));
  }
  ASSERT_GT(pairs.back().size(), 2 * pairs.front().size()) << "the soup's pairs do not grow enough";
  for (size_t f = 1; f < pairs.size(); ++f)
    ASSERT_LT(pairs[f].size(), pairs[f - 1].size() + pairs[f - 1].size() / 8) << "frame " << f << " grows too fast";
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = growing_config(device, name);
    cfg.fronts.cycle = 3;
    auto p = make_pipeline(cfg);
    p->set_topology(soup->topology());
    for (size_t f = 0; f < frames.size(); ++f) {
      const FrameStats s = p->run_frame(frames[f]);
      const PairSetDiff d = diff_pair_sets(pairs[f], p->sorted_pairs());
      ASSERT_TRUE(d.equal()) << name << " frame " << f << ": " << d.missing_count << " missing, " << d.unexpected_count
                             << " extra";
      // Updates and generates may also grow fronts, and the grid its cells ("regrid").
      const bool others_grow = s.op.find("+update") != std::string::npos ||
                               s.op.find("+generate") != std::string::npos || s.op == "regrid";
      if (f > 0 && !others_grow) {
        EXPECT_EQ(s.timing.query_reruns, 0u) << name << " frame " << f << " (" << s.op << ")";
      }
    }
  }
}

// Every pipeline with fat boxes: a superset of the exact pairs, exactly the brute-force
// set of the inflated boxes.
inline void check_margin(const std::string& device, FrameSource& source, float margin) {
  const Topology& topo = source.topology();
  std::vector<vec3f> v;
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = growing_config(device, name);
    cfg.boxes.margin = margin;
    auto p = make_pipeline(cfg);
    p->set_topology(topo);
    size_t extra = 0;
    for (uint32_t f = 0; f < source.num_frames(); ++f) {
      source.frame(f, v);
      const auto exact = sweep_oracle_pairs(topo, v, false);
      const auto expected = reference_pairs(topo, v, nullptr, margin);
      const FrameStats s = p->run_frame(v);
      const auto got = p->sorted_pairs();
      ASSERT_TRUE(contains_all(got, exact)) << name << " frame " << f << " misses exact pairs";
      const PairSetDiff d = diff_pair_sets(expected, got);
      ASSERT_TRUE(d.equal()) << name << " frame " << f << " (" << s.op << "): " << d.missing_count << " missing, "
                             << d.unexpected_count << " unexpected against the inflated boxes";
      extra += got.size() - exact.size();
    }
    EXPECT_GT(extra, 0u) << name << ": the margin added no pair";
  }
}

// Every pipeline with swept boxes: exactly the brute-force set of the boxes over each
// frame interval (the first frame its own boxes), a superset of the discrete pairs.
inline void check_swept(const std::string& device, FrameSource& source) {
  const Topology& topo = source.topology();
  std::vector<vec3f> v, prev;
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = growing_config(device, name);
    cfg.boxes.swept = true;
    auto p = make_pipeline(cfg);
    // Twice: set_topology (what --repeat does) must forget the last pass's positions.
    for (int pass = 0; pass < 2; ++pass) {
      p->set_topology(topo);
      size_t swept_only = 0;
      for (uint32_t f = 0; f < source.num_frames(); ++f) {
        source.frame(f, v);
        const auto discrete = sweep_oracle_pairs(topo, v, false);
        const auto expected = reference_pairs(topo, v, f == 0 ? nullptr : &prev, 0.0f);
        const FrameStats s = p->run_frame(v);
        const auto got = p->sorted_pairs();
        ASSERT_TRUE(contains_all(got, discrete)) << name << " frame " << f << " misses discrete pairs";
        const PairSetDiff d = diff_pair_sets(expected, got);
        ASSERT_TRUE(d.equal()) << name << " pass " << pass << " frame " << f << " (" << s.op << "): "
                               << d.missing_count << " missing, " << d.unexpected_count
                               << " unexpected against the swept boxes";
        swept_only += got.size() - discrete.size();
        prev = v;
      }
      EXPECT_GT(swept_only, 0u) << name << ": swept boxes found no pair the discrete ones miss";
    }
  }
}

// --refit-every k: tree pipelines keep the boxes of their last refit or build on the
// frames between (op "stale": only on frames not a multiple of k) and report exactly their
// overlaps, missing pairs on a fast scene; the baselines stay exact.
inline void check_lazy_refit(const std::string& device, FrameSource& source, uint32_t k) {
  const Topology& topo = source.topology();
  std::vector<vec3f> v, refitted;
  for (const auto& name : pipeline_names()) {
    PipelineConfig cfg = growing_config(device, name);
    cfg.tree.refit_every = k;
    const bool lazy = keeps_stale_boxes(name);
    EXPECT_EQ(config_conservative(cfg), !lazy) << name;
    auto p = make_pipeline(cfg);
    p->set_topology(topo);
    double recall_min = 1.0;
    uint32_t stale_frames = 0;
    for (uint32_t f = 0; f < source.num_frames(); ++f) {
      source.frame(f, v);
      const auto exact = sweep_oracle_pairs(topo, v, false);
      const FrameStats s = p->run_frame(v);
      const bool stale = s.op.rfind("stale", 0) == 0;
      ASSERT_FALSE(stale && (!lazy || f % k == 0)) << name << " frame " << f << " op " << s.op;
      stale_frames += stale;
      if (!stale) refitted = v;
      const auto expected = stale ? reference_pairs(topo, refitted, nullptr, 0.0f) : exact;
      const auto got = p->sorted_pairs();
      const PairSetDiff d = diff_pair_sets(expected, got);
      ASSERT_TRUE(d.equal()) << name << " frame " << f << " (" << s.op << "): " << d.missing_count << " missing, "
                             << d.unexpected_count << " unexpected against the "
                             << (stale ? "last refit's boxes" : "exact pairs");
      recall_min = std::min(recall_min, pair_accuracy(exact, got).recall);
    }
    if (lazy) {
      EXPECT_GE(stale_frames, source.num_frames() / 2) << name;
      EXPECT_LT(recall_min, 1.0) << name << ": stale boxes missed nothing on a fast scene";
    } else {
      EXPECT_EQ(recall_min, 1.0) << name;
    }
  }
}

}  // namespace cdb::test
