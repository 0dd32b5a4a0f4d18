// Memory accounting (exec/memory.h) and the front pipelines' buffer sizing
// (pipeline/front_query.h, docs/design.md "Memory"): the peak and what each buffer held at
// it, a peak of pipeline c bounded by what its fronts needed, and growth that stays counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/pair_set.h"
#include "cdbench/exec/host_exec.h"
#include "cdbench/exec/memory.h"
#include "scenes/generators/generators.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/plan_record.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {
namespace {

size_t bytes_of(const MemoryStats& m, const std::string& buffer) {
  for (const BufferBytes& b : m.at_peak)
    if (b.buffer == buffer) return b.bytes;
  return 0;
}

size_t sum_at_peak(const MemoryStats& m, const std::string& prefix = "") {
  size_t sum = 0;
  for (const BufferBytes& b : m.at_peak)
    if (b.buffer.compare(0, prefix.size(), prefix) == 0) sum += b.bytes;
  return sum;
}

// Bytes at the peak of one kind's front nodes: the arrays sized in front nodes, not the
// per-tree-node counters of its ordering.
size_t node_bytes(const MemoryStats& m, const std::string& kind) {
  size_t sum = 0;
  for (const char* a : {"prim", "node", "raw_prim", "raw_node", "raw_mark"}) sum += bytes_of(m, kind + "." + a);
  return sum;
}

}  // namespace

// The peak, the bytes each named buffer held at it (the sum is the peak), and a growth
// after a buffer's first reservation counted with its sizes.
TEST(MemoryStats, PeakBreakdownAndGrowths) {
  HostExec exec;
  MemoryStats m;
  {
    Array<uint32_t> a(exec.memory(), "a");
    Array<uint64_t> b(exec.memory(), "b");
    a.reserve(100);
    b.reserve(50);
    a.reserve(80);  // fits: no allocation, no growth
    EXPECT_EQ(exec.memory().stats().growths, 0u);
    a.reserve(400);  // the old 400 bytes go before the new 1600 come
    b.reserve(10);
    m = exec.memory().stats();
  }
  EXPECT_EQ(m.peak_bytes, 400 * 4 + 50 * 8);
  EXPECT_EQ(m.current_bytes, 400 * 4 + 50 * 8);
  EXPECT_EQ(sum_at_peak(m), m.peak_bytes);
  EXPECT_EQ(bytes_of(m, "a"), 1600u);
  EXPECT_EQ(bytes_of(m, "b"), 400u);
  EXPECT_EQ(m.allocations, 3u);
  EXPECT_EQ(m.growths, 1u);
  ASSERT_EQ(m.grown.size(), 1u);
  EXPECT_EQ(m.grown[0].buffer, "a");
  EXPECT_EQ(m.grown[0].first_count, 100u);
  EXPECT_EQ(m.grown[0].last_count, 400u);
  EXPECT_EQ(exec.memory().stats().current_bytes, 0u);
}

// Pipeline c on a cloth whose rolling edge makes each update sprout (fixed cycle: the same
// plan on every machine): at the peak each kind's front arrays hold no more than 17 bytes
// a node (the current front and the produced one with its marks) for at most 1.4 times the
// largest front of that kind any frame made. The probe's bound, its spare and the spare of
// a front that outgrew its buffers stay inside that; before, the current, produced and
// sorted copies (25 bytes a node) sized for a bound that took every node for a possible
// node of each kind held up to 2 times the fronts. The whole peak stays within the bvh
// pipeline's (the tree, pairs, mesh) plus those fronts, their ordering counters and the
// restructure's scratch.
TEST(MemoryStats, FrontPipelinePeakFollowsTheFrontsItMade) {
  auto wave = make_generator("cloth-wave", {{"res", 48}, {"frames", 16}});
  const Topology& topo = wave->topology();
  const size_t tris = topo.faces.size();
  PipelineConfig cfg;
  cfg.device = "cpu";
  cfg.name = "c";
  cfg.fronts.cycle = 5;
  cfg.capacity.front_per_triangle = 0.5;  // below the need: the first frame measures it
  cfg.launch.phase_timing = false;
  PipelineConfig tree_only = cfg;
  tree_only.name = "bvh";
  auto c = make_pipeline(cfg);
  auto bvh = make_pipeline(tree_only);
  c->set_topology(topo);
  bvh->set_topology(topo);
  std::vector<vec3f> v;
  uint64_t most_internal = 0, most_external = 0, updates = 0;
  for (uint32_t f = 0; f < wave->num_frames(); ++f) {
    wave->frame(f, v);
    const FrameStats s = c->run_frame(v);
    bvh->run_frame(v);
    most_internal = std::max(most_internal, s.fronts.internal);
    most_external = std::max(most_external, s.fronts.external);
    updates += s.op.find("+update") != std::string::npos;
    if (f > 0 && s.op.find("+update") != std::string::npos) {
      EXPECT_EQ(s.timing.query_reruns, 0u) << "frame " << f << ": the probe did not size the update";
    }
  }
  ASSERT_GE(updates, 2u);
  const MemoryStats m = c->memory();
  EXPECT_EQ(sum_at_peak(m), m.peak_bytes);
  for (const auto& [kind, most] : {std::pair{std::string("front_internal"), most_internal},
                                   std::pair{std::string("front_external"), most_external}}) {
    const size_t capacity = bytes_of(m, kind + ".prim") / sizeof(uint32_t);
    EXPECT_EQ(node_bytes(m, kind), 17 * capacity) << kind;
    EXPECT_LE(double(capacity), 1.4 * double(most)) << kind << ": " << capacity << " nodes held for " << most;
  }
  const size_t fronts = sum_at_peak(m, "front_") + sum_at_peak(m, "inter_front_") + sum_at_peak(m, "rigid_front_");
  const size_t ordering = 2 * 4 * 4 * tris;  // per kind: count log, two cursors, offset log
  const size_t others = m.peak_bytes - fronts;
  EXPECT_LE(fronts, 17 * size_t(1.4 * double(most_internal + most_external)) + ordering);
  EXPECT_LE(others, bvh->memory().peak_bytes + sum_at_peak(m, "restructure.") + sum_at_peak(m, "rigid_bvh."));
}

// Growth stays counted and logged, never truncated: fronts and pairs that start far too
// small grow on the first frame, which runs its query again and reports every pair.
TEST(MemoryStats, FrontGrowthIsCountedAndExact) {
  auto wave = make_generator("cloth-wave", {{"res", 24}, {"frames", 3}});
  const Topology& topo = wave->topology();
  for (const char* name : {"a", "c"}) {
    PipelineConfig cfg;
    cfg.device = "cpu";
    cfg.name = name;
    cfg.fronts.cycle = 2;
    cfg.capacity.pairs_per_triangle = 0.01;
    cfg.capacity.front_per_triangle = 0.01;
    auto p = make_pipeline(cfg);
    p->set_topology(topo);
    std::vector<vec3f> v;
    for (uint32_t f = 0; f < wave->num_frames(); ++f) {
      wave->frame(f, v);
      const FrameStats s = p->run_frame(v);
      if (f == 0) {
        EXPECT_GE(s.timing.query_reruns, 1u) << name;
      }
      const PairSetDiff d = diff_pair_sets(sweep_oracle_pairs(topo, v, false), p->sorted_pairs());
      EXPECT_TRUE(d.equal()) << name << " frame " << f << ": " << d.missing_count << " missing";
    }
    const MemoryStats m = p->memory();
    EXPECT_GE(m.growths, 3u) << name;
    size_t front_growths = 0;
    for (const BufferGrowth& g : m.grown) {
      EXPECT_LT(g.first_count, g.last_count) << name << " " << g.buffer;
      front_growths += g.buffer.rfind("front_", 0) == 0 ? g.times : 0;
    }
    EXPECT_GE(front_growths, 5u) << name << ": the five arrays of a kind grow together";
    EXPECT_EQ(sum_at_peak(m), m.peak_bytes) << name;
  }
}

}  // namespace cdb::test

namespace cdb::test {

// --rebuild-ahead: the tree and fronts built ahead hold no build scratch and no produced
// arrays of their own. The current tree and self fronts lend theirs for each build ahead and
// get them back with the adoption, so at the peak one set of each is held, whatever its
// buffers' names; and the run is as exact as its builds in frame.
namespace {

// Pipeline c on the host over a cloth wave of `frames` frames at res 32, every frame checked
// against the oracle: its memory, and how many frames built ahead and adopted.
struct WaveRun {
  MemoryStats memory;
  uint32_t ahead = 0, adopted = 0;
  uint32_t updated_ahead = 0;  // --update-ahead's adoptions
  // Frames that fork a build or update ahead, and of them those allocating inside their time.
  uint32_t forks = 0, forks_allocating = 0;
};

WaveRun run_wave(uint32_t frames, AutoSwitch rebuild_ahead, uint32_t rebuild_every, uint32_t cycle = 0,
                 AutoSwitch update_ahead = AutoSwitch::off, bool placed = false) {
  auto wave = make_generator("cloth-wave", {{"res", 32}, {"frames", frames}});
  const Topology& topo = wave->topology();
  PipelineConfig cfg;
  cfg.device = "cpu";
  cfg.name = "c";
  cfg.launch.phase_timing = false;
  cfg.tree.rebuild_ahead = rebuild_ahead;
  cfg.tree.rebuild_every = rebuild_every;
  cfg.fronts.cycle = cycle;
  cfg.fronts.update_ahead = update_ahead;
  cfg.tree.ahead_placed = placed;
  auto p = make_pipeline(cfg);
  p->set_topology(topo);
  std::vector<vec3f> v;
  WaveRun r;
  for (uint32_t f = 0; f < wave->num_frames(); ++f) {
    wave->frame(f, v);
    const FrameStats s = p->run_frame(v);
    r.ahead += s.plan && s.plan->trees == TreeStep::ahead;
    r.adopted += s.plan && s.plan->trees == TreeStep::adopt;
    r.updated_ahead += s.plan && s.plan->trees == TreeStep::adopt_update;
    const bool fork = s.plan && (s.plan->trees == TreeStep::ahead || s.plan->trees == TreeStep::update_ahead);
    r.forks += fork;
    r.forks_allocating += fork && s.timing.allocations > 0;
    const PairSetDiff d = diff_pair_sets(sweep_oracle_pairs(topo, v, false), p->sorted_pairs());
    EXPECT_TRUE(d.equal()) << "frame " << f << ": " << d.missing_count << " missing";
  }
  r.memory = p->memory();
  return r;
}

}  // namespace

TEST(MemoryStats, BuildsAheadBorrowTheScratchAndProducedArrays) {
  const WaveRun r = run_wave(12, AutoSwitch::on, 3);
  ASSERT_GE(r.adopted, 2u);
  const MemoryStats& m = r.memory;
  EXPECT_EQ(sum_at_peak(m), m.peak_bytes);
  // An array keeps its name through the lending and the swaps: the second tree's and
  // fronts' were never reserved.
  for (const char* a : {"prim_lo", "build_lo", "build_left", "morton", "morton_sorted", "new_index", "temp"}) {
    EXPECT_GT(bytes_of(m, std::string("bvh.") + a), 0u) << a;
    EXPECT_EQ(bytes_of(m, std::string("ahead_bvh.") + a), 0u) << a;
  }
  for (const char* a : {"node_box", "leaf_box", "node_escape"}) {
    EXPECT_GT(bytes_of(m, std::string("bvh.") + a), 0u) << a;
    EXPECT_GT(bytes_of(m, std::string("ahead_bvh.") + a), 0u) << a;
  }
  for (const char* kind : {"_internal.", "_external."}) {
    for (const char* a : {"raw_prim", "raw_node", "raw_mark", "order_counts"}) {
      EXPECT_GT(bytes_of(m, std::string("front") + kind + a), 0u) << kind << a;
      EXPECT_EQ(bytes_of(m, std::string("ahead_front") + kind + a), 0u) << kind << a;
    }
    EXPECT_GT(bytes_of(m, std::string("ahead_front") + kind + "prim"), 0u) << kind;
  }
}

// --rebuild-ahead reserves the second tree and fronts at a run's first build ahead: a run
// that never builds one (a cloth wave, updates every third frame) peaks where it peaks
// with builds ahead off, and holds no byte of either. The next run over the same pipeline
// that builds ahead reserves them then.
TEST(MemoryStats, SecondTreeReservedOnlyByABuildAhead) {
  // A fixed cycle: both runs make one plan, whatever their frames' times.
  const WaveRun off = run_wave(8, AutoSwitch::off, 0, 3);
  const WaveRun on = run_wave(8, AutoSwitch::on, 0, 3);
  EXPECT_EQ(off.ahead, 0u);
  EXPECT_EQ(on.ahead, 0u);
  EXPECT_EQ(on.memory.peak_bytes, off.memory.peak_bytes);
  EXPECT_EQ(sum_at_peak(on.memory, "ahead_"), 0u);
  const WaveRun built = run_wave(8, AutoSwitch::on, 3, 3);
  ASSERT_GE(built.ahead, 1u);
  EXPECT_GT(sum_at_peak(built.memory, "ahead_bvh."), 0u);
  EXPECT_GT(sum_at_peak(built.memory, "ahead_front_"), 0u);
}

// --ahead-generate place: the fronts built ahead are generated in order into the produced
// arrays the current fronts lend, which come back as the current fronts' arrays with the
// adoption, the old current ones becoming the produced ones: the second fronts hold no front
// arrays of their own, the current fronts' arrays are those of the scatter's run (the same
// spare), and the run peaks lower than with the scatter by at least the second fronts' own
// arrays, exact on every frame. A fixed plan (builds every third frame, no update): both
// runs build and generate the same fronts.
TEST(MemoryStats, FrontsPlacedAheadHoldNoFrontArraysOfTheirOwn) {
  const WaveRun scatter = run_wave(12, AutoSwitch::on, 3, 50);
  const WaveRun placed = run_wave(12, AutoSwitch::on, 3, 50, AutoSwitch::off, true);
  ASSERT_GE(placed.adopted, 2u);
  EXPECT_EQ(placed.adopted, scatter.adopted);
  EXPECT_EQ(placed.forks_allocating, 0u);
  const MemoryStats& m = placed.memory;
  EXPECT_EQ(sum_at_peak(m), m.peak_bytes);
  size_t own = 0;  // the scatter's second fronts' own arrays at its peak
  for (const char* kind : {"_internal.", "_external."}) {
    for (const char* a : {"prim", "node", "raw_prim", "raw_node", "raw_mark", "order_counts"}) {
      EXPECT_EQ(bytes_of(m, std::string("ahead_front") + kind + a), 0u) << kind << a;
      EXPECT_LE(bytes_of(m, std::string("front") + kind + a), bytes_of(scatter.memory, std::string("front") + kind + a))
          << kind << a;
    }
    for (const char* a : {"prim", "node"}) own += bytes_of(scatter.memory, std::string("ahead_front") + kind + a);
  }
  EXPECT_GT(own, 0u);
  EXPECT_LE(m.peak_bytes + own, scatter.memory.peak_bytes);
}

// A build ahead's self fronts get room for the fronts last generated on a new tree (frame
// 0's here), scaled by the pairs since where those grew, and half again: not for the current
// fronts, which updates on the degrading tree of a soup that jumps every frame grew past
// them (here 1.4 times the fresh ones scaled; n-body's held 3.4 times what its second
// build ahead generated). One
// plan: build, three updates, a build ahead, its adoption; the second fronts' arrays hold
// what the rule asks for, and the run is exact on every frame.
TEST(MemoryStats, ABuildAheadIsSizedFromTheFreshFronts) {
  // Frames 1-7: each jitters every triangle anew from its place (frame 0 does not), so the
  // pairs hold while a tree built on one frame fits the next ones badly.
  auto soup = make_generator("soup", {{"triangles", 3000}, {"distribution", "uniform"}, {"jitter", 3.0},
                                      {"frames", 8}, {"seed", 5}});
  const Topology& topo = soup->topology();
  PipelineConfig cfg;
  cfg.device = "cpu";
  cfg.name = "b";
  cfg.tree.rebuild_ahead = AutoSwitch::on;
  cfg.capacity.front_per_triangle = 0.5;  // below the need: each reservation is the rule's
  cfg.launch.phase_timing = false;
  auto p = make_pipeline(cfg);
  p->replay_plan(std::make_shared<const RecordedPlan>(
      parse_plan("cdbench-plan 1\n0 build self=generate\n1 refit self=update\n2 refit self=update\n"
                 "3 refit self=update\n4 ahead self=preserve\n5 adopt self=preserve\n6 refit self=preserve\n",
                 "p.txt")));
  p->set_topology(topo);
  std::vector<vec3f> v;
  std::vector<FrameStats> s;
  for (uint32_t f = 1; f < soup->num_frames(); ++f) {
    soup->frame(f, v);
    s.push_back(p->run_frame(v));
    const PairSetDiff d = diff_pair_sets(sweep_oracle_pairs(topo, v, false), p->sorted_pairs());
    EXPECT_TRUE(d.equal()) << "frame " << f << ": " << d.missing_count << " missing";
  }
  ASSERT_NE(s[4].op.find("ahead"), std::string::npos) << s[4].op;
  const double growth = std::max(1.0, double(s[3].pairs) / double(std::max<uint64_t>(s[0].pairs, 1)));
  const uint64_t current[2] = {s[3].fronts.internal, s[3].fronts.external};
  const uint64_t fresh[2] = {s[0].fronts.internal, s[0].fronts.external};
  const char* names[2] = {"ahead_front_internal.prim", "ahead_front_external.prim"};
  for (int k = 0; k < 2; ++k) {
    const uint64_t expected = std::min(current[k], uint64_t(std::ceil(double(fresh[k]) * growth)));
    EXPECT_EQ(bytes_of(p->memory(), names[k]), sizeof(uint32_t) * (expected + expected / 2)) << names[k];
  }
  EXPECT_GT(double(current[0]), 1.2 * double(fresh[0]) * growth) << "the updates grew the current fronts";
}

// --update-ahead reserves of the second tree its boxes alone (the copy of T_D's the side's
// update reads, 32 bytes a node), with the second self fronts: a cloth wave updated ahead
// every third frame, never rebuilt, holds no other byte of the second tree at its peak.
TEST(MemoryStats, AnUpdateAheadReservesTheSecondTreesBoxesAlone) {
  const WaveRun r = run_wave(9, AutoSwitch::on, 0, 3, AutoSwitch::on);
  ASSERT_GE(r.updated_ahead, 1u);
  EXPECT_EQ(r.ahead, 0u);
  const size_t boxes = bytes_of(r.memory, "ahead_bvh.leaf_box") + bytes_of(r.memory, "ahead_bvh.node_box");
  EXPECT_GT(boxes, 0u);
  EXPECT_EQ(sum_at_peak(r.memory, "ahead_bvh."), boxes);
  EXPECT_GT(sum_at_peak(r.memory, "ahead_front_"), 0u);
}

// --ahead-generate place with --update-ahead on: the updates ahead too are produced in
// order into the arrays the current fronts lend, so the second fronts hold no front arrays
// of their own and the run peaks lower than with the scatter by at least theirs; every frame
// exact. A cloth wave updated ahead every third frame.
TEST(MemoryStats, PlacedUpdatesAheadHoldNoFrontArraysOfTheirOwn) {
  const WaveRun scatter = run_wave(9, AutoSwitch::on, 0, 3, AutoSwitch::on);
  const WaveRun placed = run_wave(9, AutoSwitch::on, 0, 3, AutoSwitch::on, true);
  ASSERT_GE(placed.updated_ahead, 1u);
  EXPECT_EQ(placed.updated_ahead, scatter.updated_ahead);
  EXPECT_EQ(placed.forks_allocating, 0u);
  size_t own = 0;
  for (const char* kind : {"_internal.", "_external."}) {
    for (const char* a : {"prim", "node", "raw_prim", "raw_node", "raw_mark"})
      EXPECT_EQ(bytes_of(placed.memory, std::string("ahead_front") + kind + a), 0u) << kind << a;
    for (const char* a : {"prim", "node"}) own += bytes_of(scatter.memory, std::string("ahead_front") + kind + a);
  }
  EXPECT_GT(own, 0u);
  EXPECT_LE(placed.memory.peak_bytes + own, scatter.memory.peak_bytes);
}

// The frame that forks a build or an update ahead allocates nothing between its start and
// stop: the second tree and fronts it needs are reserved before its timing starts
// (FrontPipeline::reserve_ahead). Reserved inside it, a run's first fork cost 5-19x a
// steady frame on the H100. Fixed cycles: builds ahead every 4 frames, updates ahead every 3.
TEST(MemoryStats, AFrameThatForksWorkAheadAllocatesNothingInItsTime) {
  const WaveRun built = run_wave(12, AutoSwitch::on, 4);
  ASSERT_GE(built.forks, 2u);
  EXPECT_EQ(built.forks_allocating, 0u);
  const WaveRun updated = run_wave(9, AutoSwitch::on, 0, 3, AutoSwitch::on);
  ASSERT_GE(updated.forks, 2u);
  EXPECT_EQ(updated.forks_allocating, 0u);
}

// A probe before a maintenance that rebuilds the tree ahead grows no buffer: the build
// generates its own self fronts (FrontQuery::reserve_ahead) and the current ones only
// preserve until it is adopted. Before, the probe grew them to its bound for an update that
// never came (the dragon's c on the host, one plan replayed: peak 852 against 587 MiB). The
// same plan with an update after the probe grows them, and both report the same pairs.
TEST(MemoryStats, AProbeBeforeABuildAheadGrowsNoBuffer) {
  auto wave = make_generator("cloth-wave", {{"res", 48}, {"frames", 6}});
  const std::string head = "cdbench-plan 1\n0 build self=generate\n1 refit self=preserve\n2 refit self=preserve probe\n";
  std::vector<uint64_t> pairs[2];
  size_t grown_by_probe[2] = {0, 0};
  for (int ahead = 0; ahead < 2; ++ahead) {
    const std::string rest = ahead ? "3 ahead self=preserve\n4 adopt self=preserve\n5 refit self=preserve\n"
                                   : "3 refit self=update\n4 refit self=preserve\n5 refit self=preserve\n";
    PipelineConfig cfg;
    cfg.device = "cpu";
    cfg.name = "b";
    cfg.tree.rebuild_ahead = AutoSwitch::on;
    cfg.capacity.front_per_triangle = 0.5;  // below the need: the first frame measures it
    cfg.launch.phase_timing = false;
    auto p = make_pipeline(cfg);
    p->replay_plan(std::make_shared<const RecordedPlan>(parse_plan(head + rest, "p.txt")));
    p->set_topology(wave->topology());
    std::vector<vec3f> v;
    size_t before_probe = 0;
    for (uint32_t f = 0; f < wave->num_frames(); ++f) {
      wave->frame(f, v);
      const FrameStats s = p->run_frame(v);
      pairs[ahead].push_back(s.pairs);
      if (f == 1) before_probe = p->memory().current_bytes;
      if (f == 2) grown_by_probe[ahead] = p->memory().current_bytes - before_probe;
      if (f == 3) EXPECT_NE(s.op.find(ahead ? "ahead" : "update"), std::string::npos) << s.op;
    }
  }
  EXPECT_EQ(grown_by_probe[1], 0u);
  EXPECT_GT(grown_by_probe[0], 0u);
  EXPECT_EQ(pairs[0], pairs[1]);
}

}  // namespace cdb::test
