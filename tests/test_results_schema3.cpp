// Schema 3's fields (label, input_path, input_hash, noise_warning) round-trip through the
// writer and the reader, and a file without them (schema 2) still reads, with them empty.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "harness/results/results_file.h"
#include "harness/results/results_reader.h"
#include "cdbench/pipeline/run_summary.h"

namespace cdb {
namespace {

namespace fs = std::filesystem;

fs::path write_run(const std::string& name) {
  const fs::path path = fs::temp_directory_path() / ("cdb_schema3_" + std::to_string(getpid()) + "_" + name);
  RunInfo info;
  info.scene = "funnel";
  info.pipeline = "c";
  info.backend = "cpu";
  info.label = "before the change";
  info.input_path = "/scenes/funnel.json";
  info.warmup = 1;
  info.frame_first = 0;
  info.frame_last = 3;
  info.params_json = R"({"options": {"skip-adjacent": true}})";
  ResultsFile out(path, info);
  std::vector<FrameStats> frames(3);
  for (size_t k = 0; k < frames.size(); ++k) {
    frames[k].timing.total_ms = 1.0 + double(k);
    frames[k].pairs = 10 * k;
    out.append_frame(uint32_t(k), frames[k], MemoryStats{});
  }
  out.finish(summarize_run(frames, 1), MemoryStats{}, RunFindings{"0123456789abcdef", "noisy run: 12.0%"});
  return path;
}

TEST(ResultsSchema3, NewFieldsRoundTrip) {
  const fs::path path = write_run("new.h5");
  const ResultsOverview r = read_results_overview(path);
  EXPECT_EQ(r.schema_version, kResultsSchemaVersion);
  EXPECT_EQ(r.label, "before the change");
  EXPECT_EQ(r.input_path, "/scenes/funnel.json");
  EXPECT_EQ(r.input_hash, "0123456789abcdef");
  EXPECT_EQ(r.noise_warning, "noisy run: 12.0%");
  EXPECT_FALSE(r.git_sha.empty());
  EXPECT_EQ(r.frame_last, 3u);
  EXPECT_EQ(r.warmup, 1u);
  const ResultsFrames f = read_results_frames(path);
  ASSERT_EQ(f.total_ms.size(), 3u);
  EXPECT_DOUBLE_EQ(f.total_ms[2], 3.0);
  EXPECT_EQ(f.pairs[2], 20u);
  EXPECT_EQ(f.repeats[0], 1u);
  fs::remove(path);
}

TEST(ResultsSchema3, OlderFilesWithoutThemStillRead) {
  const fs::path path = write_run("old.h5");
  {
    const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(file, 0);
    for (const char* name : {"label", "input_path", "input_hash", "noise_warning"}) EXPECT_GE(H5Adelete(file, name), 0);
    H5Fclose(file);
  }
  const ResultsOverview r = read_results_overview(path);
  EXPECT_EQ(r.status, "complete");
  EXPECT_EQ(r.label, "");
  EXPECT_EQ(r.input_hash, "");
  EXPECT_EQ(r.noise_warning, "");
  fs::remove(path);
}

}  // namespace
}  // namespace cdb
