#pragma once
// The options every command that runs pipelines shares (run, verify; scenes reads
// --scenes-dir), and what the commands make of them: the pipeline configuration, the
// device, the scene.
#include <CLI/CLI.hpp>

#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "scenes/load/scene.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

struct CommonOptions {
  std::string scene = "funnel";
  std::string device = "auto";
  std::string frames;
  std::string scenes_dir;
  std::vector<std::string> sets;  // generator overrides, key=value
  // --front-cycle FILE: the recorded plan every front pipeline replays, as given ({pipeline}
  // not yet replaced); "" for auto and K, which go into config.fronts.cycle.
  std::string front_plan;
  // The pipeline options are bound straight into it; its name and device are set per
  // pipeline by make_config.
  PipelineConfig config;
  // The flags given (cli_params.h given_flags): those a pipeline ignores are said
  // (option_scope.h).
  std::vector<std::string> given;
};

// The headings of `run --help` and `verify --help`. CLI11 lists them in the order their
// first option was added, so commands add --pipeline(s) first, then add_common,
// add_restructure, their accuracy options, add_measurement with their own measurement
// options, their output options, and add_tuning last.
inline constexpr const char* kSceneGroup = "Scene";
inline constexpr const char* kPipelineGroup = "Pipeline";
inline constexpr const char* kAccuracyGroup = "Accuracy";
inline constexpr const char* kMeasurementGroup = "Measurement";
inline constexpr const char* kOutputGroup = "Output";
// Speed knobs: none changes a pair; each option's help says which devices it applies to.
inline constexpr const char* kTuningGroup = "Tuning (speed only)";

// An option that takes one of `words` into a typed field: CLI11 checks the word (the help
// lists the words) and `parse` makes the value. The word stays the option's text, which
// the results file records (cli_params.h), and `shown` is the default the help prints.
template <class T>
CLI::Option* add_choice(CLI::App* cmd, const std::string& name, T& field, const std::string& help,
                        std::vector<std::string> words, std::function<T(const std::string&)> parse,
                        const std::string& shown) {
  return cmd->add_option_function<std::string>(name, [&field, parse](const std::string& w) { field = parse(w); }, help)
      ->check(CLI::IsMember(std::move(words)))
      ->default_str(shown);
}

// Scene, pipeline and accuracy options.
void add_common(CLI::App* cmd, CommonOptions& o);
// The measurement options run and verify share (--phase-timing).
void add_measurement(CLI::App* cmd, CommonOptions& o);
// Speed knobs that change no result.
void add_tuning(CLI::App* cmd, CommonOptions& o);
// Pipeline c's restructuring (paper section 4, Formulas 1 and 2).
void add_restructure(CLI::App* cmd, CommonOptions& o);

// The pipeline names, comma-separated, for help text.
std::string pipeline_list();
// One line a pipeline: its name, what it does, its name in the paper; a help footer.
std::string pipeline_table();

// --device: auto becomes cuda when a GPU is present, else cpu.
std::string resolve_device(const std::string& device);

PipelineConfig make_config(const CommonOptions& o, const std::string& pipeline, const std::string& device);

// Every pipeline of the list, made before any work, so a bad name or option is found
// before the first one runs. Configuration errors are usage errors.
std::vector<std::unique_ptr<Pipeline>> make_pipelines(const CommonOptions& o, const std::vector<std::string>& names,
                                                      const std::string& device);

// --scenes-dir, or the installed scenes when it is not given.
std::filesystem::path scenes_dir(const std::string& given);

Scene load_scene(const CommonOptions& o);

// The build and the device, the first lines of run and verify.
void print_environment(const std::string& device);

}  // namespace cdb
