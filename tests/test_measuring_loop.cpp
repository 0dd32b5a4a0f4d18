// The measuring loop (harness/measure/measuring_loop.h) over a fake pipeline: which passes
// and frames it runs, in which order it tells them, what it hands the pipeline between
// passes, and where it stops. No timing is asserted.
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/pipeline/plan_record.h"
#include "harness/measure/measuring_loop.h"

namespace cdb {
namespace {

// Three frames of one triangle.
class FakeSource : public FrameSource {
 public:
  FakeSource() {
    topology_.faces = {{0, 1, 2}};
    topology_.num_vertices = 3;
  }
  const Topology& topology() const override { return topology_; }
  uint32_t num_frames() const override { return 3; }
  void positions(uint32_t k, std::vector<vec3d>& out) const override {
    out = {{double(k), 0, 0}, {double(k) + 1, 0, 0}, {double(k), 1, 0}};
  }
  std::string describe() const override { return "fake"; }

 private:
  Topology topology_;
};

// Reports `pairs_per_frame` pairs and a plan step on every frame, and logs what it was asked.
class FakePipeline : public Pipeline {
 public:
  FakePipeline() : Pipeline(BoxConfig{}) {}
  void set_topology(const Topology&) override { log.push_back("topology"); }
  bool replay_plan(std::shared_ptr<const RecordedPlan> plan) override {
    log.push_back("replay");
    replayed = std::move(plan);
    return true;
  }
  FrameStats run_frame(const FrameVertices&) override {
    ++frames_run;
    FrameStats s;
    s.pairs = pairs_per_frame;
    s.op = "refit";
    s.plan = PlanStep{};
    s.timing.total_ms = 1.0;
    return s;
  }
  std::vector<PrimPair> sorted_pairs() override { return {}; }
  ResidentPairs resident_pairs() const override { return {}; }
  const MemoryStats& memory() const override { return memory_; }

  std::vector<std::string> log;
  std::shared_ptr<const RecordedPlan> replayed;
  uint64_t pairs_per_frame = 4;
  uint32_t frames_run = 0;

 private:
  MemoryStats memory_;
};

// Every event as a word, and a stop after `stop_after` timed frames (0: never).
class EventLog : public MeasuringEvents {
 public:
  bool stop_requested() const override { return stop_after && timed >= stop_after; }
  void on_warmup_frame(uint32_t frame) override { log.push_back("warmup " + std::to_string(frame)); }
  void on_pass_begin(uint32_t pass) override { log.push_back("pass " + std::to_string(pass)); }
  void on_frame(uint32_t frame, uint32_t done) override {
    timed = done;
    log.push_back("frame " + std::to_string(frame));
  }
  void on_frame_recorded(uint32_t frame, const FrameStats& s) override {
    log.push_back("recorded " + std::to_string(frame) + " x" + std::to_string(s.timing.repeats));
  }

  std::vector<std::string> log;
  uint32_t timed = 0;
  uint32_t stop_after = 0;
};

MeasuringOptions untimed_warmup() {
  MeasuringOptions o;
  o.warmup = 0;
  o.warmup_ms = 0.0;
  o.load_window_ms = 0.0;
  return o;
}

TEST(MeasuringLoop, OnePassTellsEveryFrameThenItsRecord) {
  FakeSource source;
  FakePipeline pipeline;
  const MeasuringOptions options = untimed_warmup();
  MeasuringLoop loop(pipeline, source, 1, 3, nullptr, options);
  EventLog events;
  loop.run(events);
  EXPECT_EQ(events.log, (std::vector<std::string>{"pass 0", "frame 1", "recorded 1 x1", "frame 2", "recorded 2 x1"}));
  EXPECT_TRUE(pipeline.log.empty());
  EXPECT_EQ(loop.frames().size(), 2u);
  EXPECT_EQ(loop.warmup_frames(), 0u);
}

TEST(MeasuringLoop, RepeatRunsEveryPassFromAFreshStateAndReplaysPassZero) {
  FakeSource source;
  FakePipeline pipeline;
  MeasuringOptions options = untimed_warmup();
  options.repeat = 3;
  MeasuringLoop loop(pipeline, source, 0, 2, nullptr, options);
  EventLog events;
  loop.run(events);
  EXPECT_EQ(events.log, (std::vector<std::string>{"pass 0", "frame 0", "frame 1", "pass 1", "frame 0", "frame 1",
                                                  "pass 2", "frame 0", "recorded 0 x3", "frame 1", "recorded 1 x3"}));
  // Pass 0's plan handed over after it, then a fresh state before each later pass.
  EXPECT_EQ(pipeline.log, (std::vector<std::string>{"replay", "topology", "topology"}));
  ASSERT_TRUE(pipeline.replayed);
  EXPECT_EQ(pipeline.replayed->source, "pass 0");
  EXPECT_EQ(pipeline.replayed->frames.size(), 2u);
  EXPECT_EQ(loop.frames().back().timing.total_ms, 1.0);
  EXPECT_EQ(pipeline.frames_run, 6u);
}

TEST(MeasuringLoop, FreePlansReplayNothing) {
  FakeSource source;
  FakePipeline pipeline;
  MeasuringOptions options = untimed_warmup();
  options.repeat = 2;
  options.repeat_plan = RepeatPlan::free;
  MeasuringLoop loop(pipeline, source, 0, 3, nullptr, options);
  EventLog events;
  loop.run(events);
  EXPECT_EQ(pipeline.log, (std::vector<std::string>{"topology"}));
  EXPECT_FALSE(pipeline.replayed);
}

// With the frames kept in memory the warm-up ends at the end of a pass whatever its span,
// then starts the pipeline afresh.
TEST(MeasuringLoop, WarmUpOfKeptFramesRunsWholePasses) {
  FakeSource source;
  FakePipeline pipeline;
  MeasuringOptions options = untimed_warmup();
  options.warmup_ms = 1e-9;
  options.frames_kept = true;
  MeasuringLoop loop(pipeline, source, 0, 3, nullptr, options);
  EventLog events;
  loop.run(events);
  EXPECT_EQ(loop.warmup_frames(), 3u);
  EXPECT_EQ(loop.summary().warmup_frames, 3u);
  ASSERT_GE(events.log.size(), 4u);
  EXPECT_EQ(std::vector<std::string>(events.log.begin(), events.log.begin() + 4),
            (std::vector<std::string>{"warmup 0", "warmup 1", "warmup 2", "pass 0"}));
  EXPECT_EQ(pipeline.log, (std::vector<std::string>{"topology"}));
  EXPECT_EQ(loop.frames().size(), 3u);
}

// A stop during the second of three passes keeps the first, recorded as the result.
TEST(MeasuringLoop, StopBeforeTheRecordingPassKeepsTheFinishedPasses) {
  FakeSource source;
  FakePipeline pipeline;
  MeasuringOptions options = untimed_warmup();
  options.repeat = 3;
  MeasuringLoop loop(pipeline, source, 0, 2, nullptr, options);
  EventLog events;
  events.stop_after = 3;
  loop.run(events);
  EXPECT_EQ(loop.kept_passes(), 1u);
  EXPECT_EQ(loop.frames().size(), 2u);
  EXPECT_EQ(events.log.back(), "recorded 1 x1");
}

TEST(MeasuringLoop, PassesThatDisagreeOnPairsFailNamingTheFrame) {
  FakeSource source;
  FakePipeline pipeline;
  MeasuringOptions options = untimed_warmup();
  options.repeat = 2;
  MeasuringLoop loop(pipeline, source, 0, 2, nullptr, options);
  struct ChangesPairs : EventLog {
    FakePipeline* pipeline = nullptr;
    void on_pass_begin(uint32_t pass) override { pipeline->pairs_per_frame = 4 + pass; }
  } events;
  events.pipeline = &pipeline;
  try {
    loop.run(events);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 0: pass 1 reported 4 pairs, the last pass 5"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(loop.frame(), 0u);
}

TEST(MeasuringLoop, RefusesOptionsItCannotServe) {
  FakeSource source;
  FakePipeline pipeline;
  MeasuringOptions options = untimed_warmup();
  options.repeat = 0;
  EXPECT_THROW(MeasuringLoop(pipeline, source, 0, 2, nullptr, options), Error);
  options.repeat = 1;
  options.cold = true;
  EXPECT_THROW(MeasuringLoop(pipeline, source, 0, 2, nullptr, options), Error);
}

}  // namespace
}  // namespace cdb
