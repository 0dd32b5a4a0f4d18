// The results file: runs a small pipeline on the CPU, writes every frame, and reads the
// file back with the plain HDF5 C API to check attributes, row counts and values.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "scenes/generators/generators.h"
#include "harness/results/results_columns.h"
#include "harness/results/results_file.h"
#include "harness/results/results_reader.h"
#include "scenes/load/scene_label.h"
#include "cdbench/pipeline/run_summary.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {
namespace {

namespace fs = std::filesystem;

class TempDir {
 public:
  TempDir() {
    path_ = fs::temp_directory_path() / ("cdb_results_test_" + std::to_string(getpid()));
    fs::create_directories(path_);
  }
  ~TempDir() { fs::remove_all(path_); }
  fs::path operator/(const std::string& name) const { return path_ / name; }

 private:
  fs::path path_;
};

// Plain C API reads, independent of the writer's helpers.
struct File {
  hid_t id;
  explicit File(const fs::path& p) : id(H5Fopen(p.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT)) {}
  ~File() {
    if (id >= 0) H5Fclose(id);
  }
};

std::string string_attr(hid_t loc, const char* obj, const char* name) {
  hid_t a = H5Aopen_by_name(loc, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) return "<missing>";
  hid_t t = H5Aget_type(a);
  char* text = nullptr;
  std::string value = "<unreadable>";
  if (H5Tis_variable_str(t) > 0) {
    hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, H5T_VARIABLE);
    H5Tset_cset(mem, H5T_CSET_UTF8);
    if (H5Aread(a, mem, &text) >= 0 && text) value = text;
    H5free_memory(text);
    H5Tclose(mem);
  }
  H5Tclose(t);
  H5Aclose(a);
  return value;
}

double number_attr(hid_t loc, const char* obj, const char* name) {
  hid_t a = H5Aopen_by_name(loc, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  double v = -12345;
  if (a >= 0) {
    H5Aread(a, H5T_NATIVE_DOUBLE, &v);
    H5Aclose(a);
  }
  return v;
}

hsize_t rows_of(hid_t file, const std::string& dataset) {
  hid_t d = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  if (d < 0) return hsize_t(-1);
  hid_t s = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(s, dims, nullptr);
  H5Sclose(s);
  H5Dclose(d);
  return dims[0];
}

std::vector<double> numbers(hid_t file, const std::string& dataset) {
  std::vector<double> v(rows_of(file, dataset));
  hid_t d = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(d);
  return v;
}

std::vector<uint64_t> integers(hid_t file, const std::string& dataset) {
  std::vector<uint64_t> v(rows_of(file, dataset));
  hid_t d = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_UINT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Dclose(d);
  return v;
}

std::vector<std::string> texts(hid_t file, const std::string& dataset) {
  const hsize_t n = rows_of(file, dataset);
  hid_t d = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  hid_t t = H5Dget_type(d);
  const size_t width = H5Tget_size(t);
  std::vector<char> raw(n * width);
  H5Dread(d, t, H5S_ALL, H5S_ALL, H5P_DEFAULT, raw.data());
  H5Tclose(t);
  H5Dclose(d);
  std::vector<std::string> out;
  for (hsize_t i = 0; i < n; ++i) out.emplace_back(raw.data() + i * width, strnlen(raw.data() + i * width, width));
  return out;
}

struct RecordedRun {
  std::vector<FrameStats> frames;
  std::vector<MemoryStats> memory;
  std::vector<std::vector<PrimPair>> pairs;
  MemoryStats final_memory;
};

RunInfo info_for(const std::string& pipeline, uint32_t frames) {
  RunInfo info;
  info.scene = "funnel-test";
  info.scene_description = "small funnel";
  info.pipeline = pipeline;
  info.backend = "cpu";
  info.device_name = "test cpu";
  info.params_json = R"({"pipeline": {"name": ")" + pipeline + R"("}, "warmup": 1})";
  info.warmup = 1;
  info.frame_first = 0;
  info.frame_last = frames;
  info.triangles = 123;
  info.vertices = 45;
  return info;
}

// Runs `frames` frames of a small funnel through `pipeline`, appending each to `out`.
RecordedRun run_into(ResultsFile& out, const std::string& pipeline, uint32_t frames, bool with_pairs) {
  auto scene = make_generator("funnel", {{"res", 12}, {"frames", 8}});
  PipelineConfig cfg;
  cfg.name = pipeline;
  cfg.device = "cpu";
  cfg.fronts.cycle = 2;
  auto p = make_pipeline(cfg);
  p->set_topology(scene->topology());
  RecordedRun run;
  std::vector<vec3f> v;
  for (uint32_t f = 0; f < frames; ++f) {
    scene->frame(f, v);
    run.frames.push_back(p->run_frame(v));
    run.memory.push_back(p->memory());
    out.append_frame(f, run.frames.back(), run.memory.back());
    if (with_pairs) {
      run.pairs.push_back(p->sorted_pairs());
      out.write_pairs(f, run.pairs.back());
    }
  }
  run.final_memory = p->memory();
  return run;
}

// --check's narrow-phase fields: per-frame columns as given, and the summary pooling the
// checked frames' contacts over their pairs (an unchecked frame's pairs do not count).
TEST(ResultsFile, CheckedFramesRecordContacts) {
  TempDir dir;
  const fs::path path = dir / "checked.h5";
  std::vector<FrameStats> frames(3);
  frames[0].pairs = 10, frames[0].check.checked = true, frames[0].check.contacts = 4, frames[0].check.contact_precision = 0.4;
  frames[0].check.discrete_missed_contacts = 3;
  frames[1].pairs = 0, frames[1].check.checked = true, frames[1].check.contacts = 0, frames[1].check.contact_precision = 1.0;
  frames[2].pairs = 100, frames[2].check.discrete_missed_contacts = 7;  // not checked: not summed
  const MemoryStats memory;
  const RunSummary summary = summarize_run(frames, 0);
  EXPECT_EQ(summary.contacts, 4u);
  EXPECT_EQ(summary.checked_pairs, 10u);
  EXPECT_DOUBLE_EQ(summary.contact_precision, 0.4);
  EXPECT_DOUBLE_EQ(summary.contact_precision_min, 0.4);
  EXPECT_EQ(summary.discrete_missed_contacts, 3u);
  {
    RunInfo info = info_for("static", 3);
    info.contact_distance = 0.25, info.contact_substeps = 4;
    ResultsFile out(path, info);
    for (uint32_t i = 0; i < 3; ++i) out.append_frame(i, frames[i], memory);
    out.finish(summary, memory);
  }
  File f(path);
  ASSERT_GE(f.id, 0) << path;
  EXPECT_EQ(integers(f.id, "frames/contacts"), (std::vector<uint64_t>{4, 0, 0}));
  EXPECT_EQ(numbers(f.id, "frames/contact_precision"), (std::vector<double>{0.4, 1.0, 0.0}));
  EXPECT_EQ(number_attr(f.id, "summary", "contacts"), 4);
  EXPECT_EQ(number_attr(f.id, "summary", "checked_pairs"), 10);
  EXPECT_EQ(number_attr(f.id, "summary", "contact_precision"), 0.4);
  EXPECT_EQ(number_attr(f.id, "summary", "contact_precision_min"), 0.4);
  EXPECT_EQ(integers(f.id, "frames/discrete_missed_contacts"), (std::vector<uint64_t>{3, 0, 7}));
  EXPECT_EQ(number_attr(f.id, "summary", "discrete_missed_contacts"), 3);
  EXPECT_EQ(number_attr(f.id, ".", "contact_distance"), 0.25);
  EXPECT_EQ(number_attr(f.id, ".", "contact_substeps"), 4);
  const ResultsOverview o = read_results_overview(path);
  EXPECT_EQ(o.checked_frames, 2u);
  EXPECT_EQ(o.contacts, 4u);
  EXPECT_DOUBLE_EQ(o.contact_precision, 0.4);
}

// A scene with declared queries: each frame's pairs by kind are /frames columns, their
// means /summary attributes, and the reader gives both; a scene without has neither.
TEST(ResultsFile, DeclaredQueriesRecordPairsByQuery) {
  TempDir dir;
  std::vector<FrameStats> frames(3);
  const uint64_t self[] = {6, 0, 9}, inter[] = {4, 2, 0};
  for (uint32_t i = 0; i < 3; ++i) {
    frames[i].pairs = self[i] + inter[i];
    frames[i].query_pairs = QueryPairs{self[i], inter[i]};
  }
  const MemoryStats memory;
  const RunSummary summary = summarize_run(frames, 1);
  EXPECT_TRUE(summary.by_query);
  EXPECT_DOUBLE_EQ(summary.pairs_self_mean, 4.5);
  EXPECT_DOUBLE_EQ(summary.pairs_inter_mean, 1.0);
  const fs::path path = dir / "queries.h5";
  {
    ResultsFile out(path, info_for("c", 3));
    for (uint32_t i = 0; i < 3; ++i) out.append_frame(i, frames[i], memory);
    out.finish(summary, memory);
  }
  {
    File f(path);
    ASSERT_GE(f.id, 0) << path;
    EXPECT_EQ(integers(f.id, "frames/pairs_self"), (std::vector<uint64_t>{6, 0, 9}));
    EXPECT_EQ(integers(f.id, "frames/pairs_inter"), (std::vector<uint64_t>{4, 2, 0}));
    EXPECT_EQ(number_attr(f.id, "summary", "pairs_self_mean"), 4.5);
    EXPECT_EQ(number_attr(f.id, "summary", "pairs_inter_mean"), 1.0);
  }
  const ResultsFrames read = read_results_frames(path);
  EXPECT_EQ(read.pairs_self, (std::vector<uint64_t>{6, 0, 9}));
  EXPECT_EQ(read.pairs_inter, (std::vector<uint64_t>{4, 2, 0}));
  const ResultsOverview o = read_results_overview(path);
  EXPECT_DOUBLE_EQ(o.pairs_self_mean, 4.5);
  EXPECT_DOUBLE_EQ(o.pairs_inter_mean, 1.0);

  const fs::path plain = dir / "plain.h5";
  for (FrameStats& s : frames) s.query_pairs.reset();
  {
    ResultsFile out(plain, info_for("c", 3));
    for (uint32_t i = 0; i < 3; ++i) out.append_frame(i, frames[i], memory);
    out.finish(summarize_run(frames, 1), memory);
  }
  EXPECT_TRUE(read_results_frames(plain).pairs_self.empty());
  EXPECT_TRUE(std::isnan(read_results_overview(plain).pairs_self_mean));
}

// A run with --set overrides: the label and the overrides are root attributes, and the
// reader gives the label; runs of one descriptor at other sizes never share it.
TEST(ResultsFile, SetOverridesMakeTheSceneLabel) {
  TempDir dir;
  const fs::path path = dir / "overridden.h5";
  {
    RunInfo info = info_for("b", 1);
    info.scene = "funnel";
    info.scene_overrides = {{"res", 24}, {"frames", 3}, {"shape", "cone"}};
    ResultsFile out(path, info);
    out.finish(summarize_run({}, 0), MemoryStats{});
  }
  File f(path);
  ASSERT_GE(f.id, 0) << path;
  EXPECT_EQ(string_attr(f.id, "/", "scene"), "funnel");
  EXPECT_EQ(string_attr(f.id, "/", "scene_label"), "funnel[frames=3,res=24,shape=cone]");
  EXPECT_EQ(nlohmann::json::parse(string_attr(f.id, "/", "scene_overrides")),
            (nlohmann::json{{"res", 24}, {"frames", 3}, {"shape", "cone"}}));
  EXPECT_EQ(read_results_overview(path).scene_label, "funnel[frames=3,res=24,shape=cone]");

  RunInfo bad = info_for("b", 1);
  bad.scene_overrides = nlohmann::json::array({1});
  EXPECT_THROW(ResultsFile(dir / "bad.h5", bad), Error);
  EXPECT_FALSE(fs::exists(dir / "bad.h5")) << "a bad RunInfo leaves no file";
}

TEST(SceneLabel, SortsKeysAndTypesValuesAsSetReadsThem) {
  EXPECT_EQ(scene_label("funnel", nlohmann::json::object()), "funnel");
  EXPECT_EQ(scene_label("funnel", parse_set_overrides({"res=24"})), "funnel[res=24]");
  EXPECT_EQ(scene_label("crowd", parse_set_overrides({"frames=2", "count=4"})), "crowd[count=4,frames=2]");
  EXPECT_EQ(parse_set_overrides({"res=24", "name=big", "on=true"}),
            (nlohmann::json{{"res", 24}, {"name", "big"}, {"on", true}}));
  EXPECT_THROW(parse_set_overrides({"res"}), Error);
  EXPECT_THROW(parse_set_overrides({"=3"}), Error);
}

TEST(ResultsFile, CompleteRunMatchesFrameStats) {
  TempDir dir;
  const fs::path path = dir / "nested/run.h5";
  const uint32_t n = 5;
  RecordedRun run;
  {
    ResultsFile out(path, info_for("b", n));
    run = run_into(out, "b", n, true);
    out.finish(summarize_run(run.frames, 1), run.final_memory);
  }
  File f(path);
  ASSERT_GE(f.id, 0) << path;
  EXPECT_EQ(string_attr(f.id, "/", "status"), "complete");
  EXPECT_EQ(number_attr(f.id, "/", "schema_version"), double(kResultsSchemaVersion));
  EXPECT_EQ(kResultsSchemaVersion, 5);
  EXPECT_EQ(string_attr(f.id, "/", "scene"), "funnel-test");
  EXPECT_EQ(string_attr(f.id, "/", "pipeline"), "b");
  EXPECT_EQ(string_attr(f.id, "/", "backend"), "cpu");
  EXPECT_EQ(string_attr(f.id, "/", "device_name"), "test cpu");
  EXPECT_EQ(number_attr(f.id, "/", "warmup"), 1);
  EXPECT_EQ(number_attr(f.id, "/", "triangles"), 123);
  EXPECT_NE(string_attr(f.id, "/", "git_sha"), "<missing>");
  EXPECT_NE(string_attr(f.id, "/", "compiler"), "<missing>");
  EXPECT_NE(string_attr(f.id, "/", "cdbench_version"), "<missing>");
  EXPECT_EQ(string_attr(f.id, "/", "created_utc").size(), 20u);
  EXPECT_EQ(string_attr(f.id, "/", "error"), "<missing>");
  const auto params = nlohmann::json::parse(string_attr(f.id, "/", "params_json"));
  EXPECT_EQ(params["pipeline"]["name"], "b");
  EXPECT_EQ(H5Lexists(f.id, "quality", H5P_DEFAULT), 0) << "schema 2 has no /quality group";
  EXPECT_EQ(string_attr(f.id, "/", "scene_label"), "funnel-test");
  EXPECT_EQ(string_attr(f.id, "/", "scene_overrides"), "{}");

  for (const FrameColumn& c : frame_columns())
    EXPECT_EQ(rows_of(f.id, "frames/" + c.name), n) << c.name;

  const auto frame = integers(f.id, "frames/frame");
  const auto total = numbers(f.id, "frames/t_total_ms");
  const auto pairs = integers(f.id, "frames/pairs");
  const auto reruns = integers(f.id, "frames/query_reruns");
  const auto front_int = integers(f.id, "frames/front_int");
  const auto front_ext = integers(f.id, "frames/front_ext");
  const auto q_root = numbers(f.id, "frames/q_root");
  const auto op = texts(f.id, "frames/op");
  const auto bytes = integers(f.id, "frames/device_bytes");
  const auto peak = integers(f.id, "frames/device_peak_bytes");
  for (uint32_t i = 0; i < n; ++i) {
    const FrameStats& s = run.frames[i];
    EXPECT_EQ(frame[i], i);
    EXPECT_EQ(total[i], s.timing.total_ms) << "frame " << i;
    EXPECT_EQ(pairs[i], s.pairs) << "frame " << i;
    EXPECT_EQ(reruns[i], s.timing.query_reruns) << "frame " << i;
    EXPECT_EQ(front_int[i], s.fronts.internal) << "frame " << i;
    EXPECT_EQ(front_ext[i], s.fronts.external) << "frame " << i;
    EXPECT_EQ(q_root[i], s.quality.q_root) << "frame " << i;
    EXPECT_EQ(op[i], s.op) << "frame " << i;
    EXPECT_EQ(bytes[i], run.memory[i].current_bytes) << "frame " << i;
    EXPECT_EQ(peak[i], run.memory[i].peak_bytes) << "frame " << i;
    for (size_t p = 0; p < kPhaseCount; ++p)
      EXPECT_EQ(numbers(f.id, std::string("frames/t_") + kPhaseNames[p] + "_ms")[i], s.timing.phase_ms[p])
          << kPhaseNames[p] << " frame " << i;
  }
  EXPECT_EQ(op[0], "build+generate");
  EXPECT_GT(front_int[0], 0u);

  const RunSummary expected = summarize_run(run.frames, 1);
  EXPECT_EQ(number_attr(f.id, "summary", "frames"), n);
  EXPECT_EQ(number_attr(f.id, "summary", "warmup"), 1);
  EXPECT_EQ(number_attr(f.id, "summary", "t_total_ms_mean"), expected.total.mean);
  EXPECT_EQ(number_attr(f.id, "summary", "t_total_ms_p95"), expected.total.p95);
  EXPECT_EQ(number_attr(f.id, "summary", "first_frame_ms"), run.frames[0].timing.total_ms);
  EXPECT_EQ(number_attr(f.id, "summary", "t_refit_ms_frames"), double(expected.phase[size_t(Phase::refit)].count));
  EXPECT_TRUE(std::isnan(number_attr(f.id, "summary", "t_build_ms_mean")))
      << "build runs only on frame 0, a warm-up frame";
  EXPECT_EQ(number_attr(f.id, "summary", "peak_bytes"), double(run.final_memory.peak_bytes));
  // /memory: each buffer at the peak, in the executor's order; they sum to the peak.
  const auto buffers = texts(f.id, "memory/buffer");
  const auto held = integers(f.id, "memory/bytes_at_peak");
  ASSERT_EQ(buffers.size(), run.final_memory.at_peak.size());
  ASSERT_EQ(held.size(), buffers.size());
  ASSERT_FALSE(buffers.empty());
  uint64_t sum = 0;
  for (size_t i = 0; i < buffers.size(); ++i) {
    EXPECT_EQ(buffers[i], run.final_memory.at_peak[i].buffer) << i;
    EXPECT_EQ(held[i], run.final_memory.at_peak[i].bytes) << buffers[i];
    sum += held[i];
  }
  EXPECT_EQ(sum, run.final_memory.peak_bytes);
  EXPECT_NE(std::find(buffers.begin(), buffers.end(), "bvh.node_box"), buffers.end());

  for (uint32_t i = 0; i < n; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "pairs/frame_%04u", i);
    ASSERT_EQ(rows_of(f.id, name), run.pairs[i].size()) << name;
    std::vector<PrimPair> stored(run.pairs[i].size());
    hid_t d = H5Dopen2(f.id, name, H5P_DEFAULT);
    H5Dread(d, H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, stored.data());
    H5Dclose(d);
    for (size_t k = 0; k < stored.size(); ++k)
      ASSERT_TRUE(stored[k].a == run.pairs[i][k].a && stored[k].b == run.pairs[i][k].b) << name << " row " << k;
  }

  const ResultsOverview o = read_results_overview(path);
  EXPECT_EQ(o.status, "complete");
  EXPECT_EQ(o.scene_label, "funnel-test");
  EXPECT_EQ(o.triangles, 123u);
  EXPECT_EQ(o.checked_frames, 0u);
  EXPECT_EQ(o.frames_written, n);
  EXPECT_EQ(o.frames_planned, n);
  EXPECT_EQ(o.mean_ms, expected.total.mean);
  EXPECT_FALSE(o.phase_means.empty());
  for (const auto& [phase, mean] : o.phase_means) EXPECT_FALSE(std::isnan(mean)) << phase;
}

TEST(ResultsFile, AbandonedRunKeepsItsFramesAndSaysWhy) {
  TempDir dir;
  const fs::path path = dir / "abandoned.h5";
  RecordedRun run;
  {
    ResultsFile out(path, info_for("bvh", 10));
    run = run_into(out, "bvh", 3, false);
    out.abandon(summarize_run(run.frames, 1), run.final_memory, "frame 3: something broke");
  }
  File f(path);
  ASSERT_GE(f.id, 0);
  EXPECT_EQ(string_attr(f.id, "/", "status"), "incomplete");
  EXPECT_EQ(string_attr(f.id, "/", "error"), "frame 3: something broke");
  EXPECT_EQ(rows_of(f.id, "frames/t_total_ms"), 3u);
  EXPECT_EQ(number_attr(f.id, "summary", "frames"), 3);
  EXPECT_EQ(rows_of(f.id, "memory/buffer"), run.final_memory.at_peak.size());
  EXPECT_EQ(H5Lexists(f.id, "pairs", H5P_DEFAULT), 0);
  const ResultsOverview o = read_results_overview(path);
  EXPECT_EQ(o.status, "incomplete");
  EXPECT_EQ(o.frames_written, 3u);
  EXPECT_EQ(o.frames_planned, 10u);
}

TEST(ResultsFile, UnfinishedFileStaysIncomplete) {
  TempDir dir;
  const fs::path path = dir / "unfinished.h5";
  {
    ResultsFile out(path, info_for("sweep", 4));
    run_into(out, "sweep", 2, false);
  }
  File f(path);
  ASSERT_GE(f.id, 0);
  EXPECT_EQ(string_attr(f.id, "/", "status"), "incomplete");
  EXPECT_EQ(rows_of(f.id, "frames/op"), 2u);
  EXPECT_EQ(H5Lexists(f.id, "summary", H5P_DEFAULT), 0);
  const ResultsOverview o = read_results_overview(path);
  EXPECT_FALSE(o.has_summary);
  EXPECT_EQ(o.frames_written, 2u);
}

TEST(ResultsFile, ErrorsNameTheFile) {
  TempDir dir;
  const fs::path blocker = dir / "not-a-dir";
  { std::FILE* f = std::fopen(blocker.c_str(), "w"); std::fclose(f); }
  try {
    ResultsFile out(blocker / "run.h5", info_for("bvh", 1));
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not-a-dir"), std::string::npos) << e.what();
  }
  try {
    read_results_overview(blocker);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not-a-dir"), std::string::npos) << e.what();
  }
}

TEST(ResultsFile, OverlongTextIsAnErrorNamingColumnAndFrame) {
  TempDir dir;
  ResultsFile out(dir / "long.h5", info_for("bvh", 1));
  FrameStats s;
  s.op = std::string(kTextColumnBytes + 1, 'x');
  try {
    out.append_frame(7, s, MemoryStats{});
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/frames/op frame 7"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace cdb::test
