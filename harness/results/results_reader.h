#pragma once
// Reads back what `cdbench report` shows of a results file, from the schema alone
// (docs/results-format.md): the run's attributes, its status, how many frames it wrote and
// its /summary when there is one.
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/pipeline/plan_record.h"

namespace cdb {

struct ResultsOverview {
  std::string path;
  int64_t schema_version = 0;
  std::string status;  // complete | incomplete
  std::string error;   // why an incomplete run stopped, when it said
  std::string scene, pipeline, backend, device_name;
  // The scene with its --set overrides, e.g. funnel[res=24]; files of schema 1 have no
  // scene_label attribute and get it from params_json's recorded --set options.
  std::string scene_label;
  uint64_t triangles = 0;
  // Schema 3; "" in older files: run --label, the input's absolute path, its content hash
  // (written when the run completes) and the noise warning the run printed.
  std::string label, input_path, input_hash, noise_warning;
  std::string git_sha;  // the build's commit (with -dirty when it had local changes)
  uint64_t frame_first = 0, frame_last = 0, warmup = 0;
  bool cold = false;
  // params_json's "options": every option of the run, the value given or its default.
  nlohmann::json options = nlohmann::json::object();
  uint64_t frames_planned = 0;  // frame_last - frame_first
  uint64_t frames_written = 0;  // rows in /frames
  bool has_summary = false;
  uint64_t measured_frames = 0;
  double mean_ms = 0, median_ms = 0, p95_ms = 0, min_ms = 0, first_ms = 0, pairs_mean = 0;
  // Scenes with declared queries: the mean pairs within one object and between two (NaN
  // for other scenes and older files).
  double pairs_self_mean = 0, pairs_inter_mean = 0;
  uint64_t peak_bytes = 0;
  // Written by newer files only (NaN when absent): --repeat passes and the median noise
  // (relative std. dev.), host-device synchronizations per frame.
  double repeats = 0, noise_median = 0, host_syncs_mean = 0;
  // --check: frames compared with the oracle (0: unchecked, the rest NaN), the lowest
  // recall and precision over them, true contacts and contacts / reported pairs.
  uint64_t checked_frames = 0, contacts = 0;
  double recall_min = 0, precision_min = 0, contact_precision = 0;
  // Mean time of each phase that ran, by phase name, without "total".
  std::vector<std::pair<std::string, double>> phase_means;
  // Schema 4; "" and 0 in older files: --repeat-plan (replay | free), the plan file every
  // pass replayed (--front-cycle FILE) and the frames whose passes ran different plans.
  std::string repeat_plan, plan_source;
  uint64_t plan_mixed_frames = 0;
  uint64_t warmup_frames = 0;  // --warmup-ms's untimed frames (0 in files without it)
  bool has_plans = false;  // the file records its passes' plans (/plans)
  // Schema 5; "" and NaN in older files: the run's conditions (good | poor) and why they
  // were poor, the host's busy warnings, the share of its CPU time other work used before
  // the run and after the measured frames, and the CPU model.
  std::string conditions, conditions_notes, host_warning, cpu_model;
  double host_busy_before = 0, host_busy_after = 0;
  uint64_t passes_kept = 0;  // passes whose times /passes keeps (0: none, files before schema 5)
  // The GPU's conditions (harness/results/gpu_attributes.h), by attribute name: its texts
  // and its numbers (NaN: not read); neither holds a name the file lacks (files written
  // before they were recorded).
  std::map<std::string, std::string> gpu_text;
  std::map<std::string, double> gpu_number;
};

ResultsOverview read_results_overview(const std::filesystem::path& path);

// The per-frame columns `cdbench compare` works on, one entry per /frames row.
struct ResultsFrames {
  std::vector<uint64_t> frame, pairs, repeats;
  std::vector<double> total_ms;
  // --repeat: relative standard deviation of total_ms over the passes (0 with one pass;
  // files without the column read as 0).
  std::vector<double> total_noise;
  // Scenes with declared queries: pairs within one object and between two (self + inter =
  // pairs); empty for other scenes and older files.
  std::vector<uint64_t> pairs_self, pairs_inter;
};

ResultsFrames read_results_frames(const std::filesystem::path& path);

// Every pass's times per /frames row (/passes, schema 5): `passes` 0 in older files, which
// keep only each frame's mean over the passes. Rows are /frames rows; within a row, pass 0
// first, the order of /plans.
struct ResultsPasses {
  uint64_t passes = 0;
  std::vector<std::vector<double>> total_ms;  // [row][pass]
  // The timed phases' times, by phase name (all phases, or only upload without
  // --phase-timing), each [row][pass].
  std::vector<std::pair<std::string, std::vector<std::vector<double>>>> phase_ms;
};

ResultsPasses read_results_passes(const std::filesystem::path& path);

// Each pass's front plan (/plans, schema 4): none for pipelines without a frame plan and
// for older files. Each plan's source names the file, the pipeline and the pass.
struct ResultsPlans {
  std::string pipeline;
  std::vector<RecordedPlan> passes;  // by pass, the first first
};

ResultsPlans read_results_plans(const std::filesystem::path& path);

}  // namespace cdb
