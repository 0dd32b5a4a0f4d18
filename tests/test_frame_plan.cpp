// The front pipelines' frame plan alone: the paper's fixed cycle, the adaptive (rent or buy)
// maintenance on given frame costs, and pipeline c's Formula 2 decisions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "error_of.h"
#include "cdbench/pipeline/frame_plan.h"

using namespace cdb;
using cdb::test::error_of;

namespace {

// Maintenances always update, as in the paper (--regenerate off), unless a test says.
PipelineConfig cycle_config(uint32_t cycle) {
  PipelineConfig c;
  c.fronts.cycle = cycle;
  c.fronts.regenerate = false;
  return c;
}

// One letter per frame: b(uild+generate), p(reserve), u(pdate), g(enerate), r(estructure);
// the self query's operation after a refit unless the frame rebuilt.
char letter(const FramePlan& p) {
  if (p.rebuild) return 'b';
  switch (p.op(Query::self)) {
    case FrontOp::preserve: return 'p';
    case FrontOp::update: return 'u';
    case FrontOp::generate: return 'g';
    case FrontOp::restructure: return 'r';
  }
  return '?';
}

// Plans `frames` frames; cost(frame, plan) gives each frame's measured time.
template <class Cost>
std::string schedule(FramePlanner& planner, int frames, Cost cost) {
  std::string s;
  for (int f = 0; f < frames; ++f) {
    const FramePlan p = planner.plan(1000, 100);
    s += letter(p);
    planner.finish(p, {.ms = cost(f, p), .front_nodes = 100, .q_root = 1.0});
  }
  return s;
}

double flat(int, const FramePlan& p) { return p.steady() ? 1.0 : 3.0; }

}  // namespace

TEST(FramePlan, FixedCycleIsThePapersScheme) {
  FramePlanner a(FrontStrategy{}, cycle_config(4));
  EXPECT_EQ(schedule(a, 13, flat), "bpppupppupppu");
  FrontStrategy periodic;
  periodic.periodic = true;
  FramePlanner p(periodic, cycle_config(4));
  EXPECT_EQ(schedule(p, 17, flat), "bpppupppgpppupppg");
  FramePlanner every(FrontStrategy{}, cycle_config(1));
  EXPECT_EQ(schedule(every, 5, flat), "buuuu");
}

TEST(FramePlan, BalanceOnlyBeforeUpdatesOfPipelinesThatBalance) {
  FrontStrategy b;
  b.balance = true;
  PipelineConfig whole = cycle_config(2);
  whole.fronts.update_in_place = false;
  FramePlanner planner(b, whole);
  for (int f = 0; f < 6; ++f) {
    const FramePlan p = planner.plan(100, 100);
    EXPECT_EQ(p.balance, p.op(Query::self) == FrontOp::update) << "frame " << f;
    planner.finish(p, {.ms = 1.0, .front_nodes = 100, .q_root = 1.0});
  }
}

TEST(FramePlan, RebuildAndStaleFrames) {
  FrontStrategy reference;
  reference.rebuild_every_frame = true;
  FramePlanner r(reference, cycle_config(4));
  EXPECT_EQ(schedule(r, 4, flat), "bbbb");

  PipelineConfig c = cycle_config(4);
  c.tree.rebuild_every = 3;
  FramePlanner every3(FrontStrategy{}, c);
  EXPECT_EQ(schedule(every3, 8, flat), "bppbppbp");

  c = cycle_config(4);
  c.tree.refit_every = 2;
  FramePlanner stale(FrontStrategy{}, c);
  std::vector<bool> stale_frames;
  for (int f = 0; f < 5; ++f) {
    const FramePlan p = stale.plan(100, 100);
    stale_frames.push_back(p.stale);
    stale.finish(p, {.ms = 1.0, .front_nodes = 100, .q_root = 1.0});
  }
  EXPECT_EQ(stale_frames, (std::vector<bool>{false, true, false, true, false}));
}

// Fronts whose steady frames never get dearer are never updated: preserving them costs
// nothing more.
TEST(FramePlan, AdaptiveKeepsFrontsThatDoNotDegrade) {
  FramePlanner planner(FrontStrategy{}, cycle_config(0));
  const std::string s = schedule(planner, 60, flat);
  EXPECT_EQ(s, "b" + std::string(59, 'p'));
}

// Steady frames dearer by `a` per frame since the fronts were produced: the rent after n
// steady frames is a n (n - 1) / 2, and the update comes on the first frame after it
// reaches the price of an update: before one is measured the build frame's cost over a
// steady frame over kBuildPerUpdate, after, the measured update's cost over a fresh steady
// frame (`extra`).
TEST(FramePlan, AdaptiveUpdatesWhenTheRentPaidReachesTheUpdatesPrice) {
  auto steady_frames = [](double a, double price) {
    size_t n = 1;
    while (a * double(n * (n - 1)) / 2 < price - 1e-12) ++n;
    return n;
  };
  for (const double a : {0.02, 0.1, 0.5}) {
    const double build = 10.0, extra = 2.0;
    int since = 0;
    auto cost = [&](int, const FramePlan& p) {
      if (!p.steady()) {
        since = 0;
        return p.rebuild ? build : 1.0 + extra;
      }
      return 1.0 + a * since++;
    };
    FramePlanner planner(FrontStrategy{}, cycle_config(0));
    const std::string s = schedule(planner, 300, cost);
    const std::string first = "b" + std::string(steady_frames(a, (build - 1.0) / kBuildPerUpdate), 'p') + "u";
    const std::string cycle = std::string(steady_frames(a, extra), 'p') + "u";
    EXPECT_EQ(s.substr(0, first.size() + 3 * cycle.size()), first + cycle + cycle + cycle) << "a = " << a << ": " << s;
  }
}

// An update of stale fronts costs more (here `b` per frame of staleness) than one of fresh
// fronts. The price is the cheapest recent update's, so a late, dear update does not push
// the next one later still: the cycle stays as long as the fresh price makes it.
TEST(FramePlan, AdaptiveDoesNotFeedOnDearLateUpdates) {
  const double a = 0.1, fresh = 2.0, b = 1.0;
  int since = 0;
  auto cost = [&](int, const FramePlan& p) {
    if (p.rebuild) return 10.0;
    if (!p.steady()) {
      const double update = 1.0 + fresh + b * since;
      since = 0;
      return update;
    }
    return 1.0 + a * since++;
  };
  FramePlanner planner(FrontStrategy{}, cycle_config(0));
  const std::string s = schedule(planner, 400, cost);
  // The first update prices fresh + b times its staleness; the next ones price lower as
  // their cycles shorten, never higher.
  std::vector<size_t> gaps;
  for (size_t at = s.find('u'), next; (next = s.find('u', at + 1)) != std::string::npos; at = next)
    gaps.push_back(next - at);
  ASSERT_GE(gaps.size(), 10u) << s;
  EXPECT_LE(gaps.back(), gaps.front()) << s;
  EXPECT_EQ(gaps[gaps.size() - 1], gaps[gaps.size() - 2]) << s;  // settled
}

// An update that outgrew its buffers ran twice: it does not set the price once an update
// that ran once has.
TEST(FramePlan, UpdatesThatRanTwiceDoNotSetThePrice) {
  FrontMaintenance m(FrontMaintenance::kAuto);
  m.observe({.kind = FrameKind::steady, .ms = 1.0, .front_nodes = 10});
  // Ran twice, the only price so far.
  m.observe({.kind = FrameKind::updated, .ms = 9.0, .front_nodes = 10, .once = false});
  EXPECT_DOUBLE_EQ(m.price_ms(10), 8.0);
  m.produced();
  m.observe({.kind = FrameKind::steady, .ms = 1.0, .front_nodes = 10});
  m.observe({.kind = FrameKind::updated, .ms = 3.0, .front_nodes = 10});  // ran once: replaces the twice-run price
  EXPECT_DOUBLE_EQ(m.price_ms(10), 2.0);
  m.produced();
  m.observe({.kind = FrameKind::steady, .ms = 1.0, .front_nodes = 10});
  // Ran twice: ignored, however cheap.
  m.observe({.kind = FrameKind::updated, .ms = 1.5, .front_nodes = 10, .once = false});
  EXPECT_DOUBLE_EQ(m.price_ms(10), 2.0);
}

// The price follows the front's size: per node, the cheapest update so far.
TEST(FramePlan, ThePriceScalesWithTheFront) {
  FrontMaintenance m(FrontMaintenance::kAuto);
  EXPECT_FALSE(m.priced());
  m.observe({.kind = FrameKind::built, .ms = 17.0, .front_nodes = 100});  // the build frame: a guess until measured
  m.observe({.kind = FrameKind::steady, .ms = 1.0, .front_nodes = 100});
  EXPECT_DOUBLE_EQ(m.price_ms(100), 16.0 / kBuildPerUpdate);
  m.produced();
  m.observe({.kind = FrameKind::steady, .ms = 1.0, .front_nodes = 100});
  m.observe({.kind = FrameKind::updated, .ms = 3.0, .front_nodes = 100});  // 2 ms over a steady frame for 100 nodes
  EXPECT_DOUBLE_EQ(m.price_ms(300), 6.0);
  m.produced();
  m.observe({.kind = FrameKind::steady, .ms = 1.0, .front_nodes = 100});
  m.observe({.kind = FrameKind::updated, .ms = 6.0, .front_nodes = 100});  // a dearer (staler) update leaves the price
  EXPECT_DOUBLE_EQ(m.price_ms(100), 2.0);
}

// A build frame whose buffers grew ran its front pass twice: the first maintenance's price
// comes from its first pass, not from both passes and the growth between them.
TEST(FramePlan, ABuildFrameThatRanAgainIsPricedByItsFirstPass) {
  for (const bool ran_once : {true, false}) {
    FramePlanner planner(FrontStrategy{}, cycle_config(0));
    const FramePlan build = planner.plan(1000, 100);
    ASSERT_TRUE(build.rebuild);
    FramePlanner::Outcome o;
    o.ms = 17.0;
    o.ran_once = ran_once;
    o.front_nodes = 100;
    o.first_pass_ms = 9.0;
    planner.finish(build, o);
    const FramePlan steady = planner.plan(1000, 100);
    ASSERT_TRUE(steady.steady());
    planner.finish(steady, {.ms = 1.0, .front_nodes = 100, .q_root = 1.0});
    EXPECT_DOUBLE_EQ(planner.maintenance().price_ms(100), (ran_once ? 16.0 : 8.0) / kBuildPerUpdate)
        << "ran once: " << ran_once;
  }
}

// The faster the fronts degrade, the more often they are updated; the dearer the update,
// the less often.
TEST(FramePlan, AdaptiveFollowsTheScene) {
  auto updates = [](double a, double extra) {
    int since = 0;
    FramePlanner planner(FrontStrategy{}, cycle_config(0));
    const std::string s = schedule(planner, 120, [&](int, const FramePlan& p) {
      if (!p.steady()) {
        since = 0;
        return 1.0 + extra;
      }
      return 1.0 + a * since++;
    });
    return std::count(s.begin(), s.end(), 'u');
  };
  EXPECT_GT(updates(1.0, 2.0), updates(0.05, 2.0));
  EXPECT_GT(updates(0.2, 1.0), updates(0.2, 8.0));
}

// Timing noise alone lets the rent creep up: fronts that do not degrade still update now and
// then, rarely.
TEST(FramePlan, AdaptiveUnderNoiseUpdatesRarely) {
  FramePlanner planner(FrontStrategy{}, cycle_config(0));
  const std::string s = schedule(planner, 400, [](int f, const FramePlan& p) {
    const double noise = 0.02 * std::sin(f * 12.9898);
    return (p.steady() ? 1.0 : 2.0) + noise;
  });
  const auto n = std::count(s.begin(), s.end(), 'u');
  EXPECT_GE(n, 2);
  EXPECT_LE(n, 40);
}

TEST(FramePlan, AdaptivePeriodicAlternatesUpdateAndGenerate) {
  FrontStrategy periodic;
  periodic.periodic = true;
  FramePlanner planner(periodic, cycle_config(0));
  int since = 0;
  const std::string s = schedule(planner, 80, [&](int, const FramePlan& p) {
    if (!p.steady()) {
      since = 0;
      return 3.0;
    }
    return 1.0 + 0.5 * since++;
  });
  std::string maintenance;
  for (char ch : s.substr(1))
    if (ch != 'p') maintenance += ch;
  ASSERT_GE(maintenance.size(), 4u) << s;
  for (size_t k = 0; k < maintenance.size(); ++k) EXPECT_EQ(maintenance[k], k % 2 ? 'g' : 'u') << s;
}

// Pipeline c: inspection after updates once Q of the root is known; what it finds
// decides the next frame by Formula 2 on the share of leaves in candidates.
TEST(FramePlan, Formula2DecidesTheFrameAfterAnInspection) {
  FrontStrategy c;
  c.balance = c.restructure = true;
  PipelineConfig config = cycle_config(2);
  config.restructure.threshold_refit = 0.05;
  config.restructure.threshold_build = 0.5;
  config.restructure.priced = false;  // Formula 2 alone (the price: RestructuresOnlyWhereTheLastOneSavedTime)
  struct Case {
    uint32_t leaves_in_candidates;
    Formula2 decision;
    char op;
  };
  for (const Case k : {Case{10, Formula2::refit, 'p'}, Case{200, Formula2::restructure, 'r'},
                       Case{800, Formula2::rebuild, 'b'}}) {
    FramePlanner planner(c, config);
    FramePlan p = planner.plan(1000, 100);  // frame 0 builds: Q(root) becomes the reference
    EXPECT_FALSE(p.inspect);
    planner.finish(p, {.ms = 5.0, .front_nodes = 100, .q_root = 2.0});
    EXPECT_DOUBLE_EQ(planner.q_ref(), 2.0);
    p = planner.plan(1000, 100);  // frame 1 preserves
    EXPECT_FALSE(p.inspect);
    // Found nothing: not inspected.
    planner.finish(p, {.ms = 1.0, .front_nodes = 100, .q_root = 2.0, .found = {3, 99}});
    p = planner.plan(1000, 100);  // frame 2 updates and inspects
    ASSERT_EQ(p.op(Query::self), FrontOp::update);
    EXPECT_TRUE(p.inspect);
    EXPECT_EQ(p.decision, Formula2::none);
    planner.finish(p, {.ms = 2.0, .front_nodes = 100, .q_root = 2.5, .found = {4, k.leaves_in_candidates, 100000}});
    p = planner.plan(1000, 100);
    EXPECT_EQ(p.decision, k.decision);
    EXPECT_EQ(letter(p), k.op);
    if (k.decision == Formula2::restructure) {
      EXPECT_EQ(p.op(Query::inter), FrontOp::generate);  // the cross fronts name T_D's renumbered leaves
      EXPECT_EQ(p.restructuring.count, 4u);
      EXPECT_EQ(p.restructuring.leaves, k.leaves_in_candidates);
    }
    planner.finish(p, {.ms = 2.0, .front_nodes = 100, .q_root = 2.0});
    EXPECT_EQ(planner.plan(1000, 100).decision, Formula2::none);  // each inspection decides once
  }
}

TEST(FramePlan, ResetStartsOver) {
  FramePlanner planner(FrontStrategy{}, cycle_config(0));
  int since = 0;
  schedule(planner, 30, [&](int, const FramePlan& p) { return p.steady() ? 1.0 + 0.5 * since++ : (since = 0, 3.0); });
  ASSERT_TRUE(planner.maintenance().priced());
  planner.reset();
  EXPECT_EQ(planner.frame(), 0u);
  EXPECT_FALSE(planner.maintenance().priced());
  EXPECT_EQ(schedule(planner, 5, flat), "bpppp");
}

namespace {

// As schedule, with a probing preserve as 'P'.
template <class Cost>
std::string schedule_probes(FramePlanner& planner, int frames, Cost cost) {
  std::string s;
  for (int f = 0; f < frames; ++f) {
    const FramePlan p = planner.plan(1000, 100);
    EXPECT_TRUE(!p.probe || (p.op(Query::self) == FrontOp::preserve && !p.rebuild)) << "frame " << f;
    s += p.probe ? 'P' : letter(p);
    planner.finish(p, {.ms = cost(f, p), .front_nodes = 100, .q_root = 1.0});
  }
  return s;
}

}  // namespace

// A fixed cycle probes on the frame before each update, so the update's buffers are sized
// by then; --update-probe off never probes.
// Updates run in place while the fronts' order has decayed by less than the compact share,
// and produce the fronts whole from it on. Balance, which reorders a front by the offsets of
// the sort that produced it, runs only before whole updates of fronts without holes.
TEST(FramePlan, UpdatesInPlaceUntilTheOrderDecays) {
  FrontStrategy c;
  c.balance = true;
  c.restructure = true;
  for (bool in_place : {true, false}) {
    PipelineConfig cfg = cycle_config(1);
    cfg.fronts.compact_share = 0.5;
    cfg.fronts.update_in_place = in_place;
    FramePlanner planner(c, cfg);
    const FramePlan built = planner.plan(100, 100);
    ASSERT_TRUE(built.rebuild);
    planner.finish(built, {.ms = 3.0, .front_nodes = 100, .q_root = 1.0});
    for (double disorder : {0.0, 0.3, 0.49, 0.5, 2.0}) {
      const FramePlan p = planner.plan(100, 100, disorder);
      const std::string where = std::string(in_place ? "in place" : "whole") + ", disorder " + std::to_string(disorder);
      ASSERT_EQ(p.op(Query::self), FrontOp::update) << where;
      EXPECT_EQ(p.in_place, in_place && disorder < 0.5) << where;
      EXPECT_EQ(p.balance, !p.in_place && disorder == 0.0) << where;
      EXPECT_TRUE(p.inspect) << where;
    }
  }
}

// --regenerate: once a second update was measured, a maintenance generates if the build
// frame's generate (per front node made) cost less than that update; from then on each runs
// whichever of the two measured cheaper last (off: every maintenance updates). Steady frames
// grow dearer by 0.5 a frame since the fronts were produced; an update costs 2 over a
// steady frame (0.02 per front node), a generate `extra`; the build frame's generate costs
// `bound` per node (-1: not timed). Pipeline c inspects after a generate chosen as after an
// update.
TEST(FramePlan, AdaptiveMaintenanceRunsWhicheverMeasuredCheaper) {
  FrontStrategy c;
  c.restructure = true;
  for (const bool regenerate : {true, false})
  for (const double bound : {0.01, 0.03, -1.0})
  for (const double extra : {1.0, 3.0}) {
    PipelineConfig cfg = cycle_config(0);
    cfg.fronts.regenerate = regenerate;
    FramePlanner planner(c, cfg);
    int since = 0;
    std::string maintenances;
    for (int f = 0; f < 120; ++f) {
      const FramePlan p = planner.plan(1000, 100);
      double ms = 17.0;
      if (!p.rebuild && p.op(Query::self) != FrontOp::preserve) {
        maintenances += letter(p);
        EXPECT_EQ(p.inspect, planner.q_ref() > 0.0) << "frame " << f;
        ms = 1.0 + (p.op(Query::self) == FrontOp::update ? 2.0 : extra);
        since = 0;
      } else if (!p.rebuild) {
        ms = 1.0 + 0.5 * since++;
      }
      planner.finish(p,
                     {.ms = ms, .front_nodes = 100, .q_root = 1.0, .generate_per_node_ms = p.rebuild ? bound : -1.0});
    }
    ASSERT_GE(maintenances.size(), 5u) << extra;
    const std::string expected = !regenerate || bound < 0.0 || bound >= 0.02 ? "uuuuu"
                                 : extra < 2.0                               ? "uuggg"
                                                                             : "uuguu";
    EXPECT_EQ(maintenances.substr(0, 5), expected)
        << "generate " << extra << ", bound " << bound << (regenerate ? ", regenerate" : ", update only");
  }
}

TEST(FramePlan, FixedCycleProbesTheFrameBeforeAnUpdate) {
  FramePlanner planner(FrontStrategy{}, cycle_config(4));
  EXPECT_EQ(schedule_probes(planner, 13, flat), "bppPuppPuppPu");
  FramePlanner every(FrontStrategy{}, cycle_config(1));
  EXPECT_EQ(schedule_probes(every, 5, flat), "buuuu");
  PipelineConfig off = cycle_config(4);
  off.fronts.update_probe = false;
  FramePlanner unprobed(FrontStrategy{}, off);
  EXPECT_EQ(schedule_probes(unprobed, 13, flat), "bpppupppupppu");
}

// Adaptively, the frame before an update probes: the one where the rent paid and what the
// next frame is expected to pay (the last frame's cost and its rise) reach the price. With
// rent growing linearly that is exact: each update follows one probe, no frame probes that
// an update does not follow, and the updates come when the rent reaches the price
// (AdaptiveUpdatesWhenTheRentPaidReachesTheUpdatesPrice).
TEST(FramePlan, AdaptiveProbesTheFrameBeforeAnUpdate) {
  for (const double a : {0.02, 0.1, 0.5}) {
    const double build = 10.0, extra = 2.0;
    int since = 0;
    double rent = 0.0;
    auto cost = [&](int, const FramePlan& p) {
      if (!p.steady()) {
        since = 0;
        rent = 0.0;
        return p.rebuild ? build : 1.0 + extra;
      }
      rent += a * since;
      return 1.0 + a * since++;
    };
    FramePlanner planner(FrontStrategy{}, cycle_config(0));
    std::string s;
    for (int f = 0; f < 200; ++f) {
      const FramePlan p = planner.plan(1000, 100);
      const double price = planner.maintenance().price_ms(100);
      s += p.probe ? 'P' : letter(p);
      if (p.updates()) {
        EXPECT_GE(rent, price - 1e-9) << "a = " << a << ", frame " << f;
      }
      planner.finish(p, {.ms = cost(f, p), .front_nodes = 100, .q_root = 1.0});
    }
    ASSERT_NE(s.find('u'), std::string::npos) << s;
    for (size_t k = s.find('u'); k != std::string::npos; k = s.find('u', k + 1))
      EXPECT_EQ(s[k - 1], 'P') << "a = " << a << ": " << s;
    for (size_t k = s.find('P'); k != std::string::npos && k + 1 < s.size(); k = s.find('P', k + 1))
      EXPECT_EQ(s[k + 1], 'u') << "a = " << a << ": " << s;
  }
}

// A steady frame dearer than expected brings an update due unprobed: it waits a frame, which
// probes. Here the fronts cost nothing to keep until frame 10, which pays 3 ms more, past the
// first update's price at once: frame 11 comes due, probes instead, and frame 12 updates.
TEST(FramePlan, AdaptiveUpdateDueUnprobedWaitsForItsProbe) {
  FramePlanner planner(FrontStrategy{}, cycle_config(0));
  std::string s;
  for (int f = 0; f < 14; ++f) {
    const FramePlan p = planner.plan(1000, 100);
    s += p.probe ? 'P' : letter(p);
    const double ms = p.rebuild ? 10.0 : !p.steady() ? 3.0 : f >= 10 ? 4.0 : 1.0;
    planner.finish(p, {.ms = ms, .front_nodes = 100, .q_root = 1.0});
  }
  EXPECT_EQ(s, "bppppppppppPup") << "(ms: build 10, steady 1 then 4 from frame 10)";
}

// Steady frames that grew a buffer (ran twice) or recorded their frame graph paid a one-off
// cost, not rent: however dear, they bring no update nearer.
TEST(FramePlan, OneOffCostsAreNoRent) {
  for (bool grew : {true, false}) {
    FramePlanner planner(FrontStrategy{}, cycle_config(0));
    std::string s;
    for (int f = 0; f < 40; ++f) {
      const FramePlan p = planner.plan(1000, 100);
      s += letter(p);
      const bool one_off = f % 5 == 1;
      FramePlanner::Outcome o{p.rebuild ? 10.0 : one_off ? 50.0 : 1.0, !(one_off && grew), 100, 1.0, {}};
      o.recorded = one_off && !grew;
      planner.finish(p, o);
    }
    EXPECT_EQ(s, "b" + std::string(39, 'p')) << (grew ? "grew" : "recorded");
  }
}

// The rebuild-or-update choice on the figures of seven scenes (docs/front-maintenance.md):
// F, the fronts' nodes per pair after the build; the probed frame's pairs; what the probe
// counts an update would make; the frames since the build. The garment's, the spheres' and
// n-body's updates would make 2-3.3 times the fronts a rebuild makes, within 6-13 frames of
// the build; the cloths' and crumple's less. Cloth-ball's tree of the flat cloth got to 2.07
// times only after 23 frames, so it is kept. The funnel's front fits a wave of resident
// threads (270K on the H200): its update would grow it past the wave, but not to twice it.
TEST(FramePlan, RebuildsWhereAnUpdateWouldOutgrowARebuildFast) {
  struct Case {
    const char* scene;
    double fresh;
    uint64_t pairs;
    double growth;
    uint32_t age;
    bool rebuilds;
  };
  for (const Case& c : {Case{"garment", 3.33, 1218000, 2.86, 7, true},
                        Case{"spheres", 3.25, 287000, 2.78, 13, true},
                        Case{"n-body", 3.0, 500000, 3.29, 6, true},
                        Case{"n-body, a rebuilt tree", 3.0, 500000, 2.66, 11, true},
                        Case{"cloth-ball", 3.08, 840000, 2.07, 23, false},
                        Case{"crumple", 3.04, 1307000, 1.81, 12, false},
                        Case{"cloth-wave", 2.46, 266000, 1.16, 20, false},
                        Case{"funnel", 2.84, 63000, 1.6, 12, false}}) {
    for (const bool enabled : {true, false}) {
      TreeMaintenance tree(enabled);
      tree.reset(270000);
      tree.built();
      const uint64_t built_pairs = 1000000;
      tree.observe(uint64_t(c.fresh * double(built_pairs)), built_pairs);
      EXPECT_DOUBLE_EQ(tree.fresh_per_pair(), c.fresh) << c.scene;
      for (uint32_t f = 2; f < c.age; ++f) tree.observe(uint64_t(c.fresh * double(built_pairs)), c.pairs);
      EXPECT_FALSE(tree.rebuild_due()) << c.scene << ": no probe yet";
      const double rebuilt = std::max(c.fresh * double(c.pairs), 270000.0);
      tree.observe(uint64_t(c.fresh * double(built_pairs)), c.pairs, uint64_t(c.growth * rebuilt));
      EXPECT_NEAR(tree.probed_growth(), c.growth, 1e-6) << c.scene;
      EXPECT_NEAR(tree.probed_rate(), (c.growth - 1.0) / c.age, 1e-6) << c.scene;
      EXPECT_EQ(tree.rebuild_due(), enabled && c.rebuilds) << c.scene << " " << tree.probed_rate();
      tree.maintained();
      EXPECT_FALSE(tree.rebuild_due()) << c.scene << ": the probe described the fronts before the maintenance";
    }
  }
}

// The same growth reached late keeps the tree; a build starts the count again.
TEST(FramePlan, KeepsATreeThatDegradedSlowly) {
  TreeMaintenance tree(true);
  tree.reset(1);
  tree.built();
  tree.observe(3000, 1000);
  for (int f = 2; f < 40; ++f) tree.observe(3000, 1000);
  tree.observe(3000, 1000, 9000);
  EXPECT_DOUBLE_EQ(tree.probed_growth(), 3.0);
  EXPECT_FALSE(tree.rebuild_due()) << "2/40 a frame";
  tree.built();
  for (int f = 1; f < 10; ++f) tree.observe(3000, 1000);
  tree.observe(3000, 1000, 9000);
  EXPECT_TRUE(tree.rebuild_due()) << "2/10 a frame";
}

// --rebuild-growth G: the same probe rebuilds under a lower G and keeps the tree under the
// default; the planner takes G from the configuration.
TEST(FramePlan, RebuildGrowthSetsTheThreshold) {
  for (const double g : {1.2, kRebuildGrowth}) {
    TreeMaintenance tree(true);
    tree.reset(1, g);
    tree.built();
    tree.observe(3000, 1000);
    tree.observe(3000, 1000, 4800);  // an update would make 1.6 times a rebuild's fronts
    EXPECT_DOUBLE_EQ(tree.probed_growth(), 1.6);
    EXPECT_EQ(tree.rebuild_due(), g < 1.6) << "G " << g;
  }
  PipelineConfig cfg = cycle_config(0);
  EXPECT_DOUBLE_EQ(FramePlanner(FrontStrategy{}, cfg).rebuild_growth(), kRebuildGrowth);
  cfg.tree.rebuild_growth = 1.2;
  FramePlanner planner(FrontStrategy{}, cfg);
  planner.reset();
  EXPECT_DOUBLE_EQ(planner.rebuild_growth(), 1.2);
}

// Through the planner: the steady frames before a maintenance probe, and their count decides
// it (a maintenance whose rent reached the price in one frame had no probe, and updates); a
// tree whose updates would stay small keeps being updated, and off never rebuilds after the
// first frame.
TEST(FramePlan, RebuildsOnTheProbeBeforeAMaintenance) {
  for (const double growth : {3.0, 1.2}) {
    for (const bool enabled : {true, false}) {
      PipelineConfig cfg = cycle_config(0);
      cfg.tree.rebuild_degraded = enabled;
      FramePlanner planner(FrontStrategy{}, cfg);
      const uint64_t pairs = 1000000, fresh = 3 * pairs;
      std::string s;
      uint64_t since_maintenance = 0;
      for (int f = 0; f < 120; ++f) {
        const FramePlan p = planner.plan(1000, fresh);
        s += letter(p);
        const double ms = f == 0 ? 20.0 : p.rebuild ? 3.0 : p.changes_fronts() ? 2.0 : 1.0 + 0.1 * double(since_maintenance);
        FramePlanner::Outcome o{ms, true, fresh, 1.0, {}};
        o.pairs = pairs;
        o.update_yield = p.probe ? uint64_t(growth * double(fresh)) : 0;
        planner.finish(p, o);
        since_maintenance = p.rebuild || p.changes_fronts() ? 0 : since_maintenance + 1;
      }
      const size_t rebuilds = size_t(std::count(s.begin() + 1, s.end(), 'b'));
      const size_t updates = size_t(std::count(s.begin(), s.end(), 'u'));
      EXPECT_GE(rebuilds + updates, 3u) << s;
      if (enabled && growth > kRebuildGrowth) {
        EXPECT_GT(rebuilds, 5 * updates) << s << ": a maintenance with no probe before it updates";
      } else {
        EXPECT_EQ(rebuilds, 0u) << s;
      }
    }
  }
}

namespace {

// Plans `frames` frames as schedule() does and records each frame's step.
template <class Cost>
RecordedPlan record(FramePlanner& planner, int frames, Cost cost) {
  RecordedPlan plan;
  plan.source = "recorded";
  plan.records_probes = true;
  for (int f = 0; f < frames; ++f) {
    const FramePlan p = planner.plan(1000, 100);
    plan.frames.push_back({uint32_t(f), planner.step(p), 0});
    planner.finish(p, {.ms = cost(f, p), .front_nodes = 100, .q_root = 1.0});
  }
  return plan;
}

}  // namespace

// A replayed plan runs the recorded operations at the recorded frames, whatever the frames
// cost this time: the adaptive schedule of degrading fronts, replayed over flat costs that
// alone would never update.
TEST(FramePlan, ReplayRunsTheRecordedSteps) {
  const QuerySet self_only = {true, false, false};
  int since = 0;
  FramePlanner adaptive(FrontStrategy{}, cycle_config(0));
  adaptive.reset(self_only);
  const RecordedPlan plan = record(adaptive, 40, [&](int, const FramePlan& p) {
    if (!p.steady()) return (since = 0, p.rebuild ? 10.0 : 3.0);
    return 1.0 + 0.2 * since++;
  });
  ASSERT_EQ(plan_outline(plan).find("update: —"), std::string::npos) << plan_outline(plan);  // it updated
  for (const PlannedFrame& f : plan.frames) {  // only the running query has an operation
    EXPECT_TRUE(f.step.op(Query::self).has_value());
    EXPECT_FALSE(f.step.op(Query::inter).has_value());
  }
  FramePlanner replay(FrontStrategy{}, cycle_config(0));
  replay.replay(std::make_shared<const RecordedPlan>(plan));
  replay.reset(self_only);
  ASSERT_TRUE(replay.replays());
  const RecordedPlan again = record(replay, 40, flat);
  EXPECT_TRUE(frames_that_differ(plan, again).empty()) << plan_outline(plan) << "\n" << plan_outline(again);
  FramePlanner decides(FrontStrategy{}, cycle_config(0));
  decides.reset(self_only);
  EXPECT_NE(plan_outline(record(decides, 40, flat)), plan_outline(plan));  // the flat costs alone do not update
  EXPECT_EQ(error_of([&] { replay.plan(1000, 100); }), "recorded: the plan records 40 frames, and the run has more");
  // Another scene's queries are refused when the run starts.
  EXPECT_EQ(error_of([&] { replay.reset({true, true, false}); }),
            "recorded frame 0: query inter runs in this scene, and the plan gives it no operation (the plan was "
            "recorded on another scene's queries)");
}

// Pipeline c's restructure replays on the candidates the replay's own inspection found on
// the frame before; with none found it stops, naming the frame.
TEST(FramePlan, ReplayedRestructuresUseTheirOwnInspection) {
  FrontStrategy c;
  c.balance = c.restructure = true;
  const RecordedPlan plan = parse_plan(
      "cdbench-plan 1\n0 build self=generate\n1 refit self=update inspect\n"
      "2 refit self=restructure decision=restructure\n3 refit self=preserve\n",
      "c.txt");
  for (const uint32_t found : {4u, 0u}) {
    FramePlanner planner(c, cycle_config(0));
    planner.replay(std::make_shared<const RecordedPlan>(plan));
    planner.reset({true, false, false});
    FramePlan p = planner.plan(1000, 100);
    EXPECT_TRUE(p.rebuild);
    planner.finish(p, {.ms = 5.0, .front_nodes = 100, .q_root = 2.0});
    p = planner.plan(1000, 100);
    EXPECT_TRUE(p.inspect);
    EXPECT_TRUE(p.balance);  // as the strategy does before every update
    planner.finish(p, {.ms = 2.0, .front_nodes = 100, .q_root = 2.5, .found = {found, 300}});
    if (found == 0) {
      EXPECT_EQ(error_of([&] { planner.plan(1000, 100); }),
                "c.txt line 4 (frame 2): restructure, but this run's inspection of the frame before found no "
                "degraded subtree (the recording's did: the two inspections differ)");
      continue;
    }
    p = planner.plan(1000, 100);
    EXPECT_EQ(p.op(Query::self), FrontOp::restructure);
    EXPECT_EQ(p.decision, Formula2::restructure);
    EXPECT_EQ(p.restructuring.count, found);
    EXPECT_EQ(p.restructuring.leaves, 300u);
  }
  // Pipeline a has no restructure: refused before the run.
  FramePlanner a(FrontStrategy{}, cycle_config(0));
  EXPECT_EQ(error_of([&] { a.replay(std::make_shared<const RecordedPlan>(plan)); }),
            "c.txt line 3 (frame 1): restructures, Formula 2 decisions and inspections are pipeline c's (the strategy "
            "restructure); this pipeline has none");
  EXPECT_FALSE(a.replays());
}

namespace {

// Which frames probe when a planner with --update-probe `update_probe` replays `text`.
std::vector<bool> replayed_probes(const std::string& text, bool update_probe = true) {
  PipelineConfig cfg = cycle_config(0);
  cfg.fronts.update_probe = update_probe;
  FramePlanner planner(FrontStrategy{}, cfg);
  const RecordedPlan plan = parse_plan(text, "p.txt");
  planner.replay(std::make_shared<const RecordedPlan>(plan));
  planner.reset({true, false, false});
  std::vector<bool> probes;
  for (size_t f = 0; f < plan.frames.size(); ++f) {
    const FramePlan p = planner.plan(1000, 100);
    probes.push_back(p.probe);
    planner.finish(p, {.ms = 1.0, .front_nodes = 100, .q_root = 1.0});
  }
  return probes;
}

}  // namespace

// A plan that records no probe (recorded before probes were) probes on the preserve before
// each recorded update; one that records them replays them where they are, a rebuild's
// included, and --update-probe off still turns them off.
TEST(FramePlan, ReplayProbesWhereThePlanSays) {
  const std::string h = "cdbench-plan 1\n0 build self=generate\n";
  EXPECT_EQ(replayed_probes(h + "1 refit self=preserve\n2 refit self=preserve\n3 refit self=update\n"),
            (std::vector<bool>{false, false, true, false}));
  const std::string recorded = h + "1 refit self=preserve probe\n2 refit self=preserve probe\n3 build self=generate\n"
                                   "4 refit self=preserve\n5 refit self=update\n";
  EXPECT_EQ(replayed_probes(recorded), (std::vector<bool>{false, true, true, false, false, false}));
  EXPECT_EQ(replayed_probes(recorded, false), std::vector<bool>(6, false));
}

// Frames 1-3 steady at `first` + k x `growth` ms for 100 pairs from 100 front nodes (a
// fixed cycle of 4 from the build); frame 4 updates in `update_ms` and its inspection finds
// 200 of 1000 leaves holding `candidate_nodes` front nodes: Formula 2 says restructure, and
// frame 5's plan is returned.
FramePlan plan_after_inspection(FramePlanner& planner, double growth, double update_ms, uint32_t candidate_nodes) {
  FramePlan p = planner.plan(1000, 100);  // 0: build
  planner.finish(p, {.ms = 5.0, .front_nodes = 100, .q_root = 2.0, .pairs = 100});
  for (int k = 0; k < 3; ++k) {
    p = planner.plan(1000, 100);  // 1-3: preserve
    EXPECT_EQ(letter(p), 'p');
    planner.finish(p, {.ms = 1.0 + growth * k, .front_nodes = 100, .q_root = 2.0, .pairs = 100});
  }
  p = planner.plan(1000, 100);  // 4: update, inspected
  EXPECT_EQ(letter(p), 'u');
  planner.finish(p, {.ms = update_ms, .front_nodes = 100, .q_root = 2.5, .found = {4, 200, candidate_nodes},
                     .pairs = 100});
  return planner.plan(1000, 100);
}

PipelineConfig restructure_config(bool priced) {
  PipelineConfig config = cycle_config(4);
  config.restructure.threshold_refit = 0.05;
  config.restructure.threshold_build = 0.5;
  config.restructure.priced = priced;
  return config;
}

// Before a restructure was measured, the bound decides: the last stretch's rent (frames 1-3
// at 1, 1 + g, 1 + 2g ms: 3g over the cheapest) in the candidates' share of the fronts,
// against the update's cost over preserving (update - 1 ms), or one steady frame (1 ms) where
// that is less. g = 1: the candidates hold all 100 front nodes, 3 ms against 1: restructure;
// 20 of them, 0.6 ms: only refit; after a 5 ms update (4 over preserving): only refit.
// Fronts that grew no dearer (g = 0) pay no rent: only refit. Unpriced: the paper's rule.
TEST(FramePlan, FirstRestructureRunsWhereTheLastStretchsRentPays) {
  FrontStrategy c;
  c.balance = c.restructure = true;
  for (const auto& [priced, growth, update_ms, candidate_nodes, expected] :
       {std::tuple{true, 1.0, 2.0, 100u, 'r'}, std::tuple{true, 1.0, 2.0, 20u, 'p'},
        std::tuple{true, 1.0, 5.0, 100u, 'p'}, std::tuple{true, 0.0, 2.0, 100u, 'p'},
        std::tuple{false, 0.0, 2.0, 100u, 'r'}}) {
    SCOPED_TRACE(std::string(priced ? "priced" : "unpriced") + ", growth " + std::to_string(growth) + ", update " +
                 std::to_string(update_ms) + " ms, " + std::to_string(candidate_nodes) + " candidate nodes");
    FramePlanner planner(c, restructure_config(priced));
    const FramePlan p = plan_after_inspection(planner, growth, update_ms, candidate_nodes);
    EXPECT_EQ(letter(p), expected);
    EXPECT_EQ(p.decision, expected == 'r' ? Formula2::restructure : Formula2::refit);
    if (priced) {
      EXPECT_DOUBLE_EQ(planner.restructure_price().last_rent_ms(), 3.0 * growth);
    }
  }
}

// After the first restructure (frame 5, 3 ms: 2 over preserving for 200 leaves), its
// stretch (frames 6-7, steady at `after_ms` for 100 pairs) is compared with the plain one
// after the build (frames 1-3: 2 ms a frame on average): the next restructure Formula 2 asks
// for (after the update at 8, the cycle's) runs where the difference per pair, for the
// 4-frame stretch, covers the measured 2 ms. At 1 ms a frame it saved 4 ms: restructure; at
// 1.8, 0.8 ms: only refit; at 2.5 it cost more than the plain stretch: only refit. Front
// nodes do not enter: the restructured fronts hold half as many.
TEST(FramePlan, RestructuresOnlyWhereTheLastOneSavedTime) {
  FrontStrategy c;
  c.balance = c.restructure = true;
  for (const auto& [after_ms, second] : {std::pair{1.0, 'r'}, std::pair{1.8, 'p'}, std::pair{2.5, 'p'}}) {
    SCOPED_TRACE(std::to_string(after_ms) + " ms a frame after the restructure");
    FramePlanner planner(c, restructure_config(true));
    FramePlan p = plan_after_inspection(planner, 1.0, 2.0, 100);
    ASSERT_EQ(letter(p), 'r');  // 5: the bound pays (FirstRestructureRunsWhereTheLastStretchsRentPays)
    EXPECT_FALSE(planner.restructure_price().measured());
    planner.finish(p, {.ms = 3.0, .front_nodes = 100, .q_root = 2.0, .pairs = 100});
    for (int f = 6; f < 8; ++f) {
      p = planner.plan(1000, 50);  // fewer front nodes, whatever they cost
      ASSERT_EQ(letter(p), 'p') << f;
      planner.finish(p, {.ms = after_ms, .front_nodes = 50, .q_root = 2.0, .pairs = 100});
    }
    p = planner.plan(1000, 50);  // 8: update, the inspection finds 200 leaves again
    ASSERT_EQ(letter(p), 'u');
    planner.finish(p, {.ms = 2.0, .front_nodes = 50, .q_root = 2.5, .found = {4, 200, 100}, .pairs = 100});
    EXPECT_TRUE(planner.restructure_price().measured());
    p = planner.plan(1000, 50);  // 9: Formula 2 says restructure; the price decides
    EXPECT_EQ(letter(p), second);
    EXPECT_EQ(p.decision, second == 'r' ? Formula2::restructure : Formula2::refit);
  }
}

// --maintain-ahead where rebuilds are built ahead: each maintenance the cycle asks for (every
// third frame since the fronts were generated) is a rebuild built ahead (A), adopted at the
// next frame (D), which generated the fronts; no frame probes. Off: updates (u).
TEST(FramePlan, MaintenancesAheadAreRebuildsBuiltAhead) {
  for (const bool ahead : {false, true}) {
    SCOPED_TRACE(ahead ? "maintained ahead" : "updated");
    PipelineConfig cfg = cycle_config(3);
    cfg.tree.maintain_ahead = ahead ? AutoSwitch::on : AutoSwitch::off;
    FramePlanner planner(FrontStrategy{}, cfg);
    planner.reset({true, false, false}, 1, true);
    std::string s;
    for (int f = 0; f < 9; ++f) {
      const FramePlan p = planner.plan(1000, 100, 0.0, true);
      s += p.ahead ? 'A' : p.adopt ? 'D' : letter(p);
      if (ahead) {
        EXPECT_FALSE(p.probe) << "frame " << f;
      }
      planner.finish(p, {.ms = 1.0, .front_nodes = 100, .q_root = 1.0});
    }
    EXPECT_EQ(s, ahead ? "bppADppAD" : "bppuppupp");
  }
}

// --update-ahead where rebuilds are built ahead: each update the cycle asks for (every third
// frame since the fronts were generated) runs on the side (U: every front preserved in the
// frame, nothing probed or inspected) and is adopted at the next frame (V), which counts as
// the update: the cycle goes on from the fronts' generate as with updates in their frames.
// The adopting frame is priced as an update (its time and the side's), and a rebuild due
// stays a build ahead. Off, or where nothing builds ahead: updates in their frames (u).
TEST(FramePlan, UpdatesAheadRunOnTheSideAndAreAdoptedAsUpdates) {
  for (const bool ahead : {false, true}) {
    for (const bool builds_ahead : {false, true}) {
      SCOPED_TRACE(std::string(ahead ? "updated ahead" : "updated in the frame") +
                   (builds_ahead ? ", builds ahead" : ", builds in the frame"));
      PipelineConfig cfg = cycle_config(3);
      cfg.fronts.update_ahead = ahead ? AutoSwitch::on : AutoSwitch::off;
      FramePlanner planner(FrontStrategy{.restructure = true}, cfg);
      planner.reset({true, false, false}, 1, builds_ahead);
      EXPECT_EQ(planner.updates_ahead(), ahead && builds_ahead);
      std::string s;
      for (int f = 0; f < 9; ++f) {
        const FramePlan p = planner.plan(1000, 100, 0.0, true);
        const char step = p.ahead ? (p.ahead_update ? 'U' : 'A') : p.adopt ? (p.ahead_update ? 'V' : 'D') : letter(p);
        s += step;
        if (step == 'U' || step == 'V') {
          EXPECT_FALSE(p.probe || p.inspect || p.balance) << "frame " << f;
          EXPECT_FALSE(p.changes_fronts()) << "frame " << f;
          EXPECT_EQ(planner.step(p).trees, step == 'U' ? TreeStep::update_ahead : TreeStep::adopt_update);
        }
        planner.finish(p, {.ms = step == 'V' ? 2.0 : 1.0, .front_nodes = 100, .q_root = 1.0, .pairs = 100,
                           .ahead_ms = step == 'V' ? 1.5 : -1.0});
      }
      EXPECT_EQ(s, ahead && builds_ahead ? "bppUVpUVp" : "bppuppupp");
    }
  }
}

// --maintain-ahead auto (fixed cycle 3 from the fronts' generate, builds ahead): the first
// maintenance runs in its frame (u at 3), the next is built ahead (A at 6, adopted at 7, the
// next due at 10); then each runs the way whose last cycle cost less per pair. Frames cost
// 1 ms for 100 pairs, an update 3 ms. With the frames beside and after a build ahead at 2 ms
// (a tree rebuilt worse), its cycle (6-9: 8 ms over 400 pairs) costs more than the update's
// (3-5: 5 ms over 300): the next maintenances run in their frames. At 1 ms it costs less
// (4 ms over 400): the next ones are built ahead.
TEST(FramePlan, MaintenanceAutoTriesBothWaysThenRunsTheCheaper) {
  for (const double beside_ms : {2.0, 1.0}) {
    SCOPED_TRACE(std::to_string(beside_ms) + " ms beside a build ahead");
    PipelineConfig cfg = cycle_config(3);
    cfg.tree.maintain_ahead = AutoSwitch::automatic;
    FramePlanner planner(FrontStrategy{}, cfg);
    planner.reset({true, false, false}, 1, true);
    std::string s;
    bool after_ahead = false;
    for (int f = 0; f < 16; ++f) {
      const FramePlan p = planner.plan(1000, 100, 0.0, true);
      const char step = p.ahead ? 'A' : p.adopt ? 'D' : letter(p);
      s += step;
      after_ahead = p.ahead || (after_ahead && step != 'u');
      const double ms = step == 'b' ? 5.0 : step == 'u' ? 3.0 : after_ahead ? beside_ms : 1.0;
      planner.finish(p, {.ms = ms, .front_nodes = 100, .q_root = 1.0, .pairs = 100});
    }
    EXPECT_GT(planner.maintenance_choice().cost(MaintenanceWay::in_frame), 0.0);
    EXPECT_GT(planner.maintenance_choice().cost(MaintenanceWay::ahead), 0.0);
    EXPECT_EQ(s.substr(0, 8), "bppuppAD");
    EXPECT_EQ(s.substr(8), beside_ms > 1.0 ? "ppuppupp" : "ppADppAD") << s;
  }
}
