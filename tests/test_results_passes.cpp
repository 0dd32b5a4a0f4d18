// Schema 5's passes: every measured pass's frame and phase times written to /passes and read
// back, the phases kept only where they were timed, and files without them still read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "error_of.h"
#include "harness/results/results_file.h"
#include "harness/results/results_reader.h"
#include "cdbench/core/phase.h"
#include "cdbench/pipeline/run_summary.h"

namespace cdb {
namespace {

namespace fs = std::filesystem;
using test::error_of;

fs::path temp(const std::string& name) {
  return fs::temp_directory_path() / ("cdb_passes_" + std::to_string(getpid()) + "_" + name);
}

RunInfo info() {
  RunInfo i;
  i.scene = "funnel";
  i.pipeline = "b";
  i.backend = "cpu";
  i.frame_first = 0;
  i.frame_last = 3;
  i.params_json = R"({"options": {}})";
  return i;
}

// Frame f of pass p: total 10 f + p ms, its query phase a tenth of it.
FrameTiming timing(uint32_t f, uint32_t p) {
  FrameTiming t;
  t.total_ms = 10.0 * f + p;
  t.phase_ms[size_t(Phase::query)] = t.total_ms / 10;
  t.phase_ms[size_t(Phase::upload)] = 0.5;
  return t;
}

// Three frames of `passes` passes; none written to /passes when passes is 0 (a file as a
// schema 4 writer left it).
fs::path write_run(const std::string& name, uint32_t passes, bool phase_timing = true) {
  const fs::path path = temp(name);
  RunInfo i = info();
  i.phase_timing = phase_timing;
  ResultsFile out(path, i);
  std::vector<FrameStats> frames(3);
  for (uint32_t f = 0; f < 3; ++f) {
    std::vector<FrameTiming> all;
    for (uint32_t p = 0; p < passes; ++p) all.push_back(timing(f, p));
    frames[f].timing = passes ? all.back() : timing(f, 0);
    out.append_frame(f, frames[f], MemoryStats{});
    if (passes) out.append_passes(f, all);
  }
  out.finish(summarize_run(frames, 1), MemoryStats{});
  return path;
}

TEST(ResultsPasses, EveryPassRoundTrips) {
  const fs::path path = write_run("three.h5", 3);
  const ResultsPasses r = read_results_passes(path);
  ASSERT_EQ(r.passes, 3u);
  ASSERT_EQ(r.total_ms.size(), 3u);
  for (uint32_t f = 0; f < 3; ++f)
    for (uint32_t p = 0; p < 3; ++p) EXPECT_EQ(r.total_ms[f][p], 10.0 * f + p) << "frame " << f << " pass " << p;
  ASSERT_EQ(r.phase_ms.size(), kPhaseCount) << "every phase is kept when phases are timed";
  for (const auto& [name, rows] : r.phase_ms)
    if (name == "query") EXPECT_DOUBLE_EQ(rows[2][1], 2.1);
  EXPECT_EQ(read_results_overview(path).passes_kept, 3u);
  fs::remove(path);
}

TEST(ResultsPasses, WithoutPhaseTimingOnlyTheUploadIsKept) {
  const fs::path path = write_run("untimed.h5", 2, false);
  const ResultsPasses r = read_results_passes(path);
  ASSERT_EQ(r.phase_ms.size(), 1u);
  EXPECT_EQ(r.phase_ms[0].first, "upload");
  EXPECT_EQ(r.phase_ms[0].second[1][1], 0.5);
  fs::remove(path);
}

TEST(ResultsPasses, ARowOfOtherPassesIsAnErrorNamingTheFrame) {
  const fs::path path = temp("uneven.h5");
  ResultsFile out(path, info());
  FrameStats s;
  out.append_frame(0, s, MemoryStats{});
  out.append_passes(0, {timing(0, 0), timing(0, 1)});
  out.append_frame(1, s, MemoryStats{});
  EXPECT_EQ(error_of([&] { out.append_passes(1, {timing(1, 0)}); }),
            path.string() + ": /passes frame 1: 1 passes, the earlier rows 2");
  fs::remove(path);
}

TEST(ResultsPasses, FilesWithoutPassesStillRead) {
  const fs::path path = write_run("means.h5", 0);
  EXPECT_EQ(read_results_passes(path).passes, 0u);
  EXPECT_TRUE(read_results_passes(path).total_ms.empty());
  EXPECT_EQ(read_results_overview(path).passes_kept, 0u);
  fs::remove(path);
}

}  // namespace
}  // namespace cdb
