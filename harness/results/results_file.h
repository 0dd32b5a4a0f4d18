#pragma once
// One run's results file (HDF5, schema in docs/results-format.md), written as the run
// goes: the run's attributes and status "incomplete" first, one /frames row per frame,
// and only a clean end marks it "complete". A run that fails or is interrupted still
// leaves a readable file that says so. Replacing an existing file, it writes beside it
// (NAME.incomplete) and renames over it only once complete, so a finished file is never
// replaced by a worse one.
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/core/pair.h"
#include "cdbench/exec/memory.h"
#include "harness/results/gpu_attributes.h"
#include "harness/results/hdf5_handle.h"
#include "harness/results/results_columns.h"
#include "cdbench/pipeline/pipeline.h"
#include "cdbench/pipeline/run_summary.h"

namespace cdb {

// 2: scene_label and scene_overrides added, /quality (always empty) dropped, numeric
// options in params_json stored as numbers.
// 3: label, input_path, input_hash and noise_warning added (readers treat them as optional).
// 4: each pass's front plan (/plans), repeat_plan and plan_source, /frames/plan_mixed and
// /summary plan_mixed_frames added (readers treat them as optional).
// 5: every measured pass's frame and phase times (/passes) and the run's conditions (host
// load before and after the measured frames, CPU, threads, conditions verdict) added.
inline constexpr int64_t kResultsSchemaVersion = 5;

// What the caller knows about the run; the writer adds the build (version, commit,
// compilers), the host and the time.
struct RunInfo {
  std::string scene, scene_description;
  // The generator parameters `--set` overrode (an object, empty when none); with the
  // scene's name they make its label (io/scene_label.h).
  nlohmann::json scene_overrides = nlohmann::json::object();
  std::string pipeline;
  std::string label;  // run --label: the user's name for the run ("" when none)
  // The input's absolute path: the directory or descriptor given, or the named scene's
  // descriptor.
  std::string input_path;
  std::string backend;      // cuda | cpu
  std::string device_name;  // the GPU's name, or the CPU model
  int driver_version = 0, runtime_version = 0;  // CUDA's; 0 on the CPU
  std::string precision = "fp32";               // of the boxes
  // Float's spacing too coarse for the scene's features (geometry/float_spacing.h): the
  // warning the run printed, empty when none.
  std::string precision_warning;
  std::string params_json;  // every parameter of the run, defaults included
  uint32_t warmup = 0;
  uint32_t frame_first = 0, frame_last = 0;  // the range asked for, half-open
  uint64_t triangles = 0, vertices = 0;
  double copy_gbps = 0.0;  // the device's copy bandwidth, measured at the run's start
  bool cold = false;       // --cold: caches flushed before every frame
  // --check's contacts: triangles within this distance (--contact-distance), the frame
  // interval sampled at this many substeps (--contact-substeps).
  double contact_distance = 0.0;
  uint32_t contact_substeps = 0;
  // --repeat-plan: how the passes' front plans were made (replay: later passes replayed the
  // first pass's; free: each pass planned its own), and --front-cycle FILE: the plan every
  // pass replayed ("" when none).
  std::string repeat_plan = "replay";
  std::string plan_source;
  // --phase-timing: each phase timed (else only the frame and its upload), so /passes keeps
  // every phase's times or only those two.
  bool phase_timing = true;
  // The conditions the run started in: the host's CPU model, its online cores and the
  // OpenMP threads the run used, and the share of its CPU time in use by other work just
  // before the run (NaN: not measured); the host's busy warning printed then ("" when none).
  std::string cpu_model;
  uint64_t host_cores = 0, omp_threads = 0;
  double host_busy_before = std::nan("");
  std::string host_warning;
};

// Known only once every frame has run.
struct RunFindings {
  // The input's content hash (core/content_hash.h, 16 hex digits); "" when not known.
  std::string input_hash;
  // The noise warning the run printed (harness/measure/noise_check.h); "" when none.
  std::string noise_warning;
  // The share of the host's CPU time in use by other work right after the measured frames
  // (NaN: not measured) and its busy warning then ("" when none).
  double host_busy_after = std::nan("");
  std::string host_warning_after;
  // The GPU's readings before and after the measured passes (absent, with the reason, on
  // the host executor and where NVML is not there).
  GpuConditions gpu;
  // Why the run's conditions were poor (a busy host, a noise warning, the GPU's
  // conditions), "" when good.
  std::string poor_conditions;
};

class ResultsFile {
 public:
  // in_place: the file is written at its path from the start (there is nothing there to
  // keep). staged: it is written to PATH.incomplete, which replaces PATH once complete; a
  // run that does not finish leaves PATH as it was and its own file as PATH.incomplete.
  enum class Placement { in_place, staged };
  // Creates the file (replacing one of that name; parent directories are made; a file that
  // could not be made whole is removed). Every write that fails on the system's side (a
  // full disk, a file size limit) throws "writing results to FILE failed: <the system's
  // reason>".
  ResultsFile(const std::filesystem::path& path, const RunInfo& info, Placement placement = Placement::in_place);
  // Closes without touching the status: a file never finished stays "incomplete". The
  // members close in reverse order of declaration, the file last.
  ~ResultsFile() = default;
  ResultsFile(const ResultsFile&) = delete;
  ResultsFile& operator=(const ResultsFile&) = delete;

  void append_frame(uint32_t frame, const FrameStats& stats, const MemoryStats& memory);
  // /passes: the times of the frame of the last append_frame in every pass, pass 0 first
  // (the order of /plans); the group is made by the first call, every call has as many.
  void append_passes(uint32_t frame, const std::vector<FrameTiming>& passes);
  // /plans: what `frame` ran in pass `pass` (0: the first); the group is made by the first.
  void append_plan_step(uint32_t pass, uint32_t frame, const PlanStep& step);
  // /pairs/frame_NNNN: the frame's sorted pairs as an (n, 2) array of triangle indices.
  void write_pairs(uint32_t frame, const std::vector<PrimPair>& pairs);
  // Writes /summary and what the run learned about itself by its end, marks the file
  // complete and closes it.
  void finish(const RunSummary& summary, const MemoryStats& memory, const RunFindings& findings = {});
  // Writes /summary of the frames so far and the error, leaves the status "incomplete"
  // and closes the file. Never throws: it runs while another error is on its way out.
  void abandon(const RunSummary& summary, const MemoryStats& memory, const std::string& error) noexcept;

  uint64_t rows() const { return rows_; }
  // Where the file is now: PATH.incomplete while a staged file is written and after it was
  // abandoned, PATH once finished.
  const std::filesystem::path& path() const { return path_; }
  // The path asked for: path() too unless the file is staged.
  const std::filesystem::path& target() const { return target_; }
  // False once a write failed on the system's side: the file on disk then holds what the
  // last flush wrote, or may not be readable at all.
  bool intact() const { return !broken_; }

 private:
  void create(const RunInfo& info);
  // Runs `write` on the open file, failing as io_failed does on a system-side error; `what`
  // names the write ("frame 3") when the file is already closed.
  template <class Write>
  void writing(const std::string& what, Write write);
  // One row appended to each of `datasets`, the columns `cols` of `row`; `at` names the
  // row in messages ("/frames/<column> frame 3").
  template <class Row>
  void append_row(const std::vector<TableColumn<Row>>& cols, std::vector<h5::Handle>& datasets, uint64_t& rows,
                  const Row& row, const std::string& group, const std::string& row_name);
  template <class Row>
  std::vector<h5::Handle> create_columns(hid_t group, const std::string& group_name,
                                         const std::vector<TableColumn<Row>>& cols);
  void write_summary(const RunSummary& summary, const MemoryStats& memory);
  void write_memory(const MemoryStats& memory);
  void close(const char* status);
  void flush_now_and_then();
  // Rethrows a system-side failure as "writing results to FILE failed: <reason>" and
  // forgets the file's HDF5 ids: closing them would flush HDF5's cache again, which after a
  // failed write crashes inside the library (the descriptor closes at exit).
  [[noreturn]] void io_failed(const h5::IoError& e);
  void forget_handles() noexcept;

  std::filesystem::path target_;  // the path asked for
  std::filesystem::path path_;    // the path written
  std::string where_;  // the path written, for messages
  bool broken_ = false;
  h5::Handle file_, frames_, pairs_, plans_, passes_;
  std::vector<h5::Handle> columns_;       // one dataset per frame_columns() entry
  std::vector<h5::Handle> plan_columns_;  // one dataset per plan_columns() entry
  std::vector<h5::Handle> query_pair_columns_;  // one per query_pair_columns() entry, or none
  // /passes: (frames x passes) datasets, t_total_ms first, then the timed phases'.
  std::vector<h5::Handle> pass_columns_;
  std::vector<int> pass_phases_;  // the phase of each pass column after the first
  bool phase_timing_ = true;
  uint64_t pass_rows_ = 0, pass_count_ = 0;
  h5::Handle text_type_;
  std::string host_warning_;  // printed before the run; the finish adds the one after
  uint64_t rows_ = 0, plan_rows_ = 0;
  std::chrono::steady_clock::time_point last_flush_;
};

}  // namespace cdb
