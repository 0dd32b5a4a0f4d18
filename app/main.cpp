// cdbench command line: parses options, wires scenes to pipelines, prints results.
// Nothing algorithmic lives here.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numeric>
#include <optional>

#include "bruteforce/sweep_oracle.h"
#include "core/build_info.h"
#include "core/error.h"
#include "cli_params.h"
#include "exit_codes.h"
#include "frame_range.h"
#include "geometry/cached_frames.h"
#include "geometry/float_spacing.h"
#include "geometry/position_rounding.h"
#include "io/obj_writer.h"
#include "io/results_file.h"
#include "io/scene.h"
#include "io/scene_label.h"
#include "output_path.h"
#include "pipeline/config_json.h"
#include "pipeline/device_probe.h"
#include "pipeline/pipeline.h"
#include "progress.h"
#include "report.h"
#include "results_table.h"
#include "run_loop.h"
#include "slurm_script.h"
#include "sweep_plan.h"
#include "sweep_runner.h"
#include "version_text.h"

using namespace cdb;

namespace {

struct CommonOptions {
  std::string scene = "funnel";
  std::string device = "auto";
  std::string frames;
  std::string scenes_dir;
  int morton_bits = 63;
  uint32_t rebuild_every = 0;
  std::string front_cycle = "auto";
  PipelineConfig restructure;  // the restructure_* and threshold_* fields
  bool skip_adjacent = false;
  float box_margin = 0.0f;
  std::string boxes = "discrete";
  std::string box_precision = "fp32";
  uint32_t refit_every = 1;
  std::string cuda_graph = "on";
  std::string dependent_launch = "on";
  std::string phase_timing = "on";
  std::string preserve_warp = "auto";
  uint32_t refit_top_leaves = kRefitTopMaxLeaves;
  std::vector<std::string> sets;  // generator overrides, key=value
};

// The headings of `run --help` and `verify --help`. CLI11 lists them in the order their
// first option was added, so commands add --pipeline(s) first, then add_common,
// add_restructure, their own options, and add_tuning last.
constexpr const char* kSceneGroup = "Scene";
constexpr const char* kPipelineGroup = "Pipeline";
constexpr const char* kAccuracyGroup = "Accuracy";
constexpr const char* kMeasurementGroup = "Measurement";
constexpr const char* kOutputGroup = "Output";
constexpr const char* kTuningGroup = "GPU tuning";

// Scene, pipeline and accuracy options every command that runs pipelines shares.
void add_common(CLI::App* cmd, CommonOptions& o) {
  cmd->add_option("--scene", o.scene, "scene name, .json descriptor, or directory of mesh frames")
      ->group(kSceneGroup)
      ->capture_default_str();
  cmd->add_option("--device", o.device, "cuda, cpu, or auto (cuda when a GPU is present)")
      ->group(kPipelineGroup)
      ->check(CLI::IsMember({"auto", "cuda", "cpu"}))
      ->capture_default_str();
  cmd->add_option("--set", o.sets, "override a generator parameter of a procedural scene: key=value (repeatable)")
      ->group(kSceneGroup);
  cmd->add_option("--frames", o.frames, "frame range A:B (half-open), A: or A; default all")->group(kSceneGroup);
  cmd->add_option("--scenes-dir", o.scenes_dir, "where named scenes live")->group(kSceneGroup);
  cmd->add_option("--rebuild-every", o.rebuild_every,
                  "bvh pipeline: rebuild every K frames (0: build on the first frame only)")
      ->group(kPipelineGroup)
      ->capture_default_str();
  cmd->add_option("--front-cycle", o.front_cycle,
                  "front pipelines: when fronts are updated instead of preserved; auto: once the measured growth of "
                  "the steady frames' cost since the last update has paid for one (rent or buy); K: every K-th frame "
                  "since the fronts were generated (the paper's fixed cycle)")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            if (v == "auto") return "";
            const bool digits = !v.empty() && v.size() < 10 && v.find_first_not_of("0123456789") == std::string::npos;
            return digits && std::stoul(v) > 0 ? "" : "auto or a positive whole number of frames, not " + v;
          },
          "auto|K"))
      ->capture_default_str();
  cmd->add_flag("--skip-adjacent", o.skip_adjacent,
                "co-vertex filtering: do not report pairs of triangles that share a vertex (oracle too)")
      ->group(kAccuracyGroup);
  cmd->add_option("--box-margin", o.box_margin,
                  "fat boxes: inflate every triangle box by this much (scene units) on each side; conservative "
                  "(recall stays 1 against the exact oracle, precision drops); all pipelines")
      ->group(kAccuracyGroup)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--boxes", o.boxes,
                  "discrete: each triangle's box at the frame; swept: its box over the frame interval (previous and "
                  "current positions); swept is conservative with respect to the discrete oracle; all pipelines")
      ->group(kAccuracyGroup)
      ->check(CLI::IsMember({"discrete", "swept"}))
      ->capture_default_str();
  cmd->add_option("--box-precision", o.box_precision,
                  "fp32: the boxes of the positions rounded to float; fp64: the positions rebased on the first "
                  "frame's centre in double before rounding, for scenes far from the origin (a run warns when fp32 "
                  "cannot hold a scene); q16: fp32 boxes snapped outward onto a 16-bit grid per axis over the "
                  "frame's vertex bounds, as a 16-bit box format stores them; all conservative against the double "
                  "geometry (recall stays 1, precision drops); all pipelines")
      ->group(kAccuracyGroup)
      ->check(CLI::IsMember({"fp32", "fp64", "q16"}))
      ->capture_default_str();
  cmd->add_option("--refit-every", o.refit_every,
                  "NOT CONSERVATIVE: front pipelines and bvh refit the hierarchy only every K frames and keep stale "
                  "boxes in between, so pairs can be missed (recall < 1 under --check); sweep, hash, grid and brute "
                  "ignore it; 1: every frame")
      ->group(kAccuracyGroup)
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  // --front-cycle is declared above with the other pipeline options; its heading:
  cmd->get_option("--front-cycle")->group(kPipelineGroup);
}

// Speed knobs that change no result (and --phase-timing, a measurement choice). Their
// defaults were tuned on the H100 (sm_90); where a default depends on the GPU the help says so.
void add_tuning(CLI::App* cmd, CommonOptions& o) {
  cmd->add_option("--morton-bits", o.morton_bits, "Morton code width (all devices)")
      ->group(kTuningGroup)
      ->check(CLI::IsMember({30, 63}))
      ->capture_default_str();
  cmd->add_option("--cuda-graph", o.cuda_graph,
                  "front pipelines on cuda: capture the steady-state frame (refit + preserve) in a CUDA graph once "
                  "and replay it while its launches stay the same; off: plain launches every frame")
      ->group(kTuningGroup)
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd->add_option("--dependent-launch", o.dependent_launch,
                  "cuda: launch every kernel with programmatic stream serialization, so it is scheduled while the "
                  "kernel before it runs and waits for it on the device; off: plain launches. Per architecture: "
                  "a Hopper (sm_90) feature, the kernels' wait is compiled for sm_90 and later only; its effect "
                  "on earlier GPUs is not measured")
      ->group(kTuningGroup)
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd->add_option("--phase-timing", o.phase_timing,
                  "time each phase of a frame with events; off: only the frame and its upload (no event between "
                  "kernels, which in a CUDA graph costs a node and keeps the next kernel from launching early)")
      ->group(kMeasurementGroup)
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  cmd->add_option("--preserve-warp", o.preserve_warp,
                  "front pipelines on cuda: preserve shares each front node's traversal with the idle lanes of its "
                  "warp; auto: while the fronts fit in " + std::to_string(kPreserveWarpWaves) +
                      " waves of the GPU's resident threads (per architecture: SMs x threads per SM, read from "
                      "the GPU at run time)")
      ->group(kTuningGroup)
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  cmd->add_option("--refit-top-leaves", o.refit_top_leaves,
                  "front pipelines and bvh: trees of up to this many leaves refit their top (the nodes whose leaves "
                  "span refit tiles) in one block of threads, larger trees hand it over between blocks; 0: always "
                  "hand over. The default was measured on the H100; other GPUs may want another")
      ->group(kTuningGroup)
      ->check(CLI::Range(0u, kRefitTopLeavesLimit))
      ->capture_default_str();
}

// Pipeline c's restructuring (paper section 4, Formulas 1 and 2).
void add_restructure(CLI::App* cmd, CommonOptions& o) {
  PipelineConfig& r = o.restructure;
  cmd->add_option("--restructure-quality", r.restructure_quality,
                  "pipeline c: a subtree is degraded when its Q exceeds this times Q(root) after the last rebuild")
      ->group(kPipelineGroup)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--restructure-min-leaves", r.restructure_min_leaves,
                  "pipeline c: smallest candidate subtree, in leaves")
      ->group(kPipelineGroup)
      ->check(CLI::Range(2u, 0x7FFFFFFFu))
      ->capture_default_str();
  cmd->add_option("--restructure-max-fraction", r.restructure_max_fraction,
                  "pipeline c: largest candidate subtree, as a share of all leaves")
      ->group(kPipelineGroup)
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--threshold-refit", r.threshold_refit,
                  "pipeline c, Formula 2: below this share of leaves in candidates, only refit")
      ->group(kPipelineGroup)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--threshold-build", r.threshold_build,
                  "pipeline c, Formula 2: from this share of leaves in candidates on, rebuild instead of restructuring")
      ->group(kPipelineGroup)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

std::string pipeline_list() {
  std::string list;
  for (const auto& n : pipeline_names()) list += (list.empty() ? "" : ", ") + n;
  return list;
}

std::string resolve_device(const std::string& device) {
  if (device != "auto") return device;
  return cuda_device_info().available ? "cuda" : "cpu";
}

PipelineConfig make_config(const CommonOptions& o, const std::string& pipeline,
                           const std::string& device) {
  PipelineConfig c;
  c.name = pipeline;
  c.device = device;
  c.morton_bits = o.morton_bits == 30 ? MortonBits::b30 : MortonBits::b63;
  c.rebuild_every = o.rebuild_every;
  c.front_cycle = o.front_cycle == "auto" ? 0u : uint32_t(std::stoul(o.front_cycle));
  c.skip_adjacent = o.skip_adjacent;
  c.box_margin = o.box_margin;
  c.swept_boxes = o.boxes == "swept";
  c.box_precision = parse_box_precision(o.box_precision);
  c.refit_every = o.refit_every;
  c.cuda_graph = o.cuda_graph == "on";
  c.dependent_launch = o.dependent_launch == "on";
  c.phase_timing = o.phase_timing == "on";
  c.preserve_warp = parse_preserve_warp(o.preserve_warp);
  c.refit_top_leaves = o.refit_top_leaves;
  c.restructure_quality = o.restructure.restructure_quality;
  c.restructure_min_leaves = o.restructure.restructure_min_leaves;
  c.restructure_max_fraction = o.restructure.restructure_max_fraction;
  c.threshold_refit = o.restructure.threshold_refit;
  c.threshold_build = o.restructure.threshold_build;
  return c;
}

// key=value pairs from --set: values parsed as JSON where they are (numbers, true, ...),
// else taken as strings.
nlohmann::json parse_overrides(const std::vector<std::string>& sets) { return parse_set_overrides(sets); }

Scene load_scene(const CommonOptions& o) {
  return open_scene(o.scene, o.scenes_dir.empty() ? default_scenes_dir() : std::filesystem::path(o.scenes_dir),
                    parse_overrides(o.sets));
}

void print_environment(const std::string& device) {
  const BuildInfo& b = build_info();
  std::printf("cdbench %s  commit %s  %s  %s%s%s\n", CDBENCH_VERSION, b.git_sha, b.build_type,
              b.cxx_compiler, *b.cuda_compiler ? "  nvcc " : "", b.cuda_compiler);
  const CudaDeviceInfo info = cuda_device_info();
  if (device == "cuda")
    std::printf("device: %s (driver %d, runtime %d, %.1f GiB)\n", info.name.c_str(),
                info.driver_version, info.runtime_version, double(info.total_bytes) / (1 << 30));
  else
    std::printf("device: cpu (%d OpenMP threads)%s%s\n", omp_threads(),
                info.available ? "" : "; no GPU: ", info.available ? "" : info.reason.c_str());
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find_first_not_of(" \t", line.find(':') + 1));
  return "unknown cpu";
}

struct RunOptions {
  std::string pipeline = "c";  // the paper's scheme
  uint32_t warmup = 1;
  bool quiet = false;
  std::string out;
  bool save_pairs = false;
  std::string check = "off";
  uint32_t repeat = 1;
  double max_noise = 0.0;  // percent on the command line, a fraction here
  bool cold = false;
  double contact_distance = 0.0;                     // as given; used as a float
  uint32_t contact_substeps = ContactCheck{}.substeps;
};

// --contact-distance and --contact-substeps, checked: a finite float distance >= 0, at
// least one substep, and only with --check (they say what --check counts).
ContactCheck contact_check(const RunOptions& r, uint32_t check_every) {
  ContactCheck c;
  c.distance = float(r.contact_distance);
  c.substeps = r.contact_substeps;
  if (!(r.contact_distance >= 0) || !std::isfinite(c.distance)) {
    char given[32];
    std::snprintf(given, sizeof given, "%g", r.contact_distance);
    fail_usage(std::string("--contact-distance ") + given + ": expected a finite distance >= 0 (within the float range)");
  }
  if (c.substeps == 0) fail_usage("--contact-substeps 0: expected at least 1 (1: the two frames only)");
  if (!check_every && (c.distance != ContactCheck{}.distance || c.substeps != ContactCheck{}.substeps))
    fail_usage("--contact-distance and --contact-substeps say what --check counts: they need --check");
  return c;
}

// --check every | N | off: frames between checks against the oracle (0: none).
uint32_t check_interval(const std::string& check) {
  if (check == "off") return 0;
  if (check == "every") return 1;
  uint32_t n = 0;
  const auto [end, ec] = std::from_chars(check.data(), check.data() + check.size(), n);
  if (ec != std::errc() || end != check.data() + check.size() || n == 0)
    fail_usage("--check " + check + ": expected every, off or a positive frame interval");
  return n;
}

// What the results file records about the run besides its frames.
RunInfo run_info(const CommonOptions& o, const RunOptions& r, const Scene& scene, const PipelineConfig& config,
                 FrameRange range, const nlohmann::json& cli_options) {
  const bool gpu = config.device == "cuda";
  const CudaDeviceInfo info = gpu ? cuda_device_info() : CudaDeviceInfo{};
  RunInfo run;
  run.scene = scene.name;
  run.scene_description = scene.description;
  run.scene_overrides = scene.overrides;
  run.pipeline = r.pipeline;
  run.backend = config.device;
  run.device_name = gpu ? info.name : cpu_model() + " (" + std::to_string(omp_threads()) + " OpenMP threads)";
  run.driver_version = info.driver_version;
  run.runtime_version = info.runtime_version;
  run.warmup = r.warmup;
  run.frame_first = range.first;
  run.frame_last = range.last;
  run.triangles = scene.source->topology().faces.size();
  run.vertices = scene.source->topology().num_vertices;
  run.cold = r.cold;
  run.precision = box_precision_name(config.box_precision);
  run.contact_distance = double(float(r.contact_distance));
  run.contact_substeps = r.contact_substeps;
  const auto scenes_dir = o.scenes_dir.empty() ? default_scenes_dir() : std::filesystem::path(o.scenes_dir);
  run.params_json = nlohmann::json{{"command", "run"},
                                   {"options", cli_options},
                                   {"pipeline_config", to_json(config)},
                                   {"resolved",
                                    {{"device", config.device},
                                     {"scene", scene.name},
                                     {"scenes_dir", scenes_dir.string()},
                                     {"frame_first", range.first},
                                     {"frame_last", range.last},
                                     {"warmup", r.warmup},
                                     {"repeat", r.repeat},
                                     {"max_noise", r.max_noise},
                                     {"cold", r.cold},
                                     {"contact_distance", double(float(r.contact_distance))},
                                     {"contact_substeps", r.contact_substeps}}}}
                        .dump();
  return run;
}

// Pipelines named by --pipeline: one, or several separated by commas, run one after the
// other on the same frames (kept in memory) so they can be compared within one run.
std::vector<std::string> split_pipelines(const std::string& list) {
  std::vector<std::string> names;
  size_t start = 0;
  for (;;) {
    const size_t comma = list.find(',', start);
    names.push_back(list.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    if (names.back().empty()) fail_usage("--pipeline " + list + ": empty pipeline name");
    if (comma == std::string::npos) return names;
    start = comma + 1;
  }
}

// Every pipeline of the list, made before any work, so a bad name or option is found
// before the first one runs. Configuration errors are usage errors.
std::vector<std::unique_ptr<Pipeline>> make_pipelines(const CommonOptions& o, const std::vector<std::string>& names,
                                                      const std::string& device) {
  std::vector<std::unique_ptr<Pipeline>> pipelines;
  for (const auto& name : names) {
    try {
      pipelines.push_back(make_pipeline(make_config(o, name, device)));
    } catch (const UsageError&) {
      throw;
    } catch (const Error& e) {
      fail_usage(e.what());
    }
  }
  return pipelines;
}

// --out with {pipeline} replaced by the pipeline's name.
std::string results_path(const std::string& pattern, const std::string& pipeline) {
  std::string path = pattern;
  const size_t at = path.find("{pipeline}");
  if (at != std::string::npos) path.replace(at, 10, pipeline);
  return path;
}

int run_command(const CommonOptions& o, const RunOptions& r, const nlohmann::json& cli_options) {
  const std::string device = resolve_device(o.device);
  const std::vector<std::string> names = split_pipelines(r.pipeline);
  const ContactCheck contact = contact_check(r, check_interval(r.check));
  if (names.size() > 1 && !r.out.empty() && r.out.find("{pipeline}") == std::string::npos)
    fail_usage("--out " + r.out + ": several pipelines need {pipeline} in the file name");
  std::vector<std::unique_ptr<Pipeline>> pipelines = make_pipelines(o, names, device);
  if (!r.out.empty())
    for (const auto& name : names) check_output_path(results_path(r.out, name));
  print_environment(device);
  Scene scene = load_scene(o);
  const Topology& topo = scene.source->topology();
  const FrameRange range = parse_frame_range(o.frames, scene.source->num_frames());
  std::printf("scene: %s — %s\n       %zu triangles, %u vertices, frames %u:%u\n",
              scene.name.c_str(), scene.description.c_str(), topo.faces.size(),
              topo.num_vertices, range.first, range.last);
  const BoxPrecision precision = parse_box_precision(o.box_precision);
  const std::string spacing_warning =
      range.last > range.first ? float_spacing_warning(*scene.source, range.first, precision == BoxPrecision::fp64) : "";
  if (!spacing_warning.empty()) std::printf("warning: %s\n", spacing_warning.c_str());
  // Measured once, before any frame: the yardstick of the bandwidth floor; and the cache
  // flush of --cold, allocated here rather than in the frame loop.
  const std::unique_ptr<DeviceProbe> probe = make_device_probe(device);
  const double copy_gbps = probe->copy_bandwidth_gbps();
  std::printf("copy bandwidth: %.0f GB/s (%s, measured; read + written)\n", copy_gbps, device.c_str());
  std::unique_ptr<FrameSource> cached;
  if (names.size() > 1 || r.repeat > 1) cached = std::make_unique<CachedFrames>(*scene.source);
  const FrameSource& frames = cached ? *cached : *scene.source;
  for (size_t p = 0; p < names.size(); ++p) {
    const std::string& name = names[p];
    const PipelineConfig config = make_config(o, name, device);
    // Released after its run, so pipelines do not hold their buffers side by side.
    const std::unique_ptr<Pipeline> pipeline = std::move(pipelines[p]);
    pipeline->set_topology(topo);
    std::printf("pipeline: %s on %s\n", name.c_str(), device.c_str());
    RunOptions one = r;
    one.pipeline = name;
    one.out = results_path(r.out, name);
    std::optional<ResultsFile> out;
    if (!one.out.empty()) {
      RunInfo info = run_info(o, one, scene, config, range, cli_options);
      info.copy_gbps = copy_gbps;
      info.precision_warning = spacing_warning;
      out.emplace(one.out, info);
    }
    RunLoopOptions loop;
    loop.warmup = r.warmup;
    loop.frame_lines = !r.quiet;
    loop.list_growth = !r.quiet;
    loop.progress = Progress::mode_for(r.quiet);
    loop.save_pairs = r.save_pairs;
    loop.check_every = check_interval(r.check);
    loop.repeat = r.repeat;
    loop.max_noise = r.max_noise / 100.0;
    loop.cold = r.cold;
    loop.probe = probe.get();
    loop.copy_gbps = copy_gbps;
    loop.oracle = [&topo, &o](const std::vector<vec3d>& v) { return sweep_oracle_pairs(topo, v, o.skip_adjacent); };
    loop.faces = &topo.faces;
    loop.contact = contact;
    if (!config_conservative(config))
      loop.accuracy_warning = "--refit-every " + std::to_string(config.refit_every) +
                              " keeps stale boxes between refits: NOT conservative, pairs can be missed";
    if (const int rc = run_frames(*pipeline, frames, range, out ? &*out : nullptr, loop)) return rc;
  }
  return 0;
}

int verify_command(const CommonOptions& o, std::vector<std::string> pipelines,
                   size_t brute_limit) {
  const std::string device = resolve_device(o.device);
  if (pipelines.empty())
    for (const auto& n : pipeline_names())
      if (n != oracle_pipeline()) pipelines.push_back(n);
  std::vector<std::unique_ptr<Pipeline>> runs = make_pipelines(o, pipelines, device);
  print_environment(device);
  Scene scene = load_scene(o);
  const Topology& topo = scene.source->topology();
  const FrameRange range = parse_frame_range(o.frames, scene.source->num_frames());
  const bool brute_oracle = topo.faces.size() <= brute_limit;
  // The oracle sees the same fat, swept or quantized boxes only as the brute-force pipeline.
  if (!brute_oracle && (o.box_margin > 0 || o.boxes != "discrete" || o.box_precision == "q16"))
    fail_usage("verify --box-margin/--boxes swept/--box-precision q16 needs the brute-force oracle (raise --brute-limit)");
  std::printf("verify: scene %s (%zu triangles), frames %u:%u, device %s, oracle %s\n",
              scene.name.c_str(), topo.faces.size(), range.first, range.last, device.c_str(),
              brute_oracle ? "brute force (same device)" : "sort-and-sweep (cpu)");
  std::unique_ptr<Pipeline> oracle;
  if (brute_oracle) {
    oracle = make_pipeline(make_config(o, oracle_pipeline(), device));
    oracle->set_topology(topo);
  }
  for (const auto& run : runs) run->set_topology(topo);
  std::vector<uint64_t> mismatched_frames(pipelines.size(), 0);
  // Each pipeline against the oracle of the floats it ran on (exact), and against the
  // scene's double geometry: none of its pairs may be missed (position_rounding.h says
  // when that holds), and the extra ones are float's blur.
  const BoxPrecision precision = parse_box_precision(o.box_precision);
  const bool keeps_double_pairs = precision == BoxPrecision::fp64 || o.box_margin == 0;
  std::vector<uint64_t> double_missed(pipelines.size(), 0), double_extra(pipelines.size(), 0);
  uint64_t double_pairs = 0;
  PositionRounding rounding(precision == BoxPrecision::fp64);
  std::vector<vec3d> positions;
  std::vector<vec3f> vertices;
  for (uint32_t f = range.first; f < range.last; ++f) {
    scene.source->positions(f, positions);
    rounding.round(positions, vertices);
    std::vector<PrimPair> expected;
    if (oracle) {
      oracle->run_frame(positions);
      expected = oracle->sorted_pairs();
    } else {
      expected = sweep_oracle_pairs(topo, vertices, o.skip_adjacent);
    }
    const std::vector<PrimPair> exact = sweep_oracle_pairs(topo, positions, o.skip_adjacent);
    double_pairs += exact.size();
    for (size_t p = 0; p < runs.size(); ++p) {
      runs[p]->run_frame(positions);
      const std::vector<PrimPair> reported = runs[p]->sorted_pairs();
      const PairSetDiff d = diff_pair_sets(expected, reported);
      if (!d.equal()) {
        ++mismatched_frames[p];
        print_mismatch(pipelines[p], f, d);
      }
      const PairSetDiff g = diff_pair_sets(exact, reported, 0);
      double_missed[p] += g.missing_count;
      double_extra[p] += g.unexpected_count;
    }
  }
  bool ok = true;
  for (size_t p = 0; p < runs.size(); ++p) {
    const bool lost = keeps_double_pairs && double_missed[p] > 0;
    std::printf("  %-12s %s (%u frames); double geometry: %llu of %llu pairs missed%s, %llu extra\n",
                pipelines[p].c_str(), mismatched_frames[p] ? "MISMATCH" : "exact", range.last - range.first,
                static_cast<unsigned long long>(double_missed[p]), static_cast<unsigned long long>(double_pairs),
                lost ? " (LOST)" : "", static_cast<unsigned long long>(double_extra[p]));
    ok = ok && mismatched_frames[p] == 0 && !lost;
  }
  if (o.refit_every > 1)
    std::printf("verify: --refit-every %u is not conservative: bvh and the front pipelines may miss pairs\n",
                o.refit_every);
  std::printf("verify: %s\n", ok ? "all pipelines match the oracle" : "FAILED");
  return ok ? 0 : 1;
}

int scenes_list(const CommonOptions& o) {
  const auto dir = o.scenes_dir.empty() ? default_scenes_dir() : std::filesystem::path(o.scenes_dir);
  // A scene whose data is not installed (e.g. assimp-testmodels) is listed with the reason,
  // and the others still are.
  for (const auto& name : list_scenes(dir)) {
    try {
      const Scene s = open_scene(name, dir);
      std::printf("%-14s %9zu triangles %5u frames  %s\n", name.c_str(),
                  s.source->topology().faces.size(), s.source->num_frames(), s.description.c_str());
    } catch (const Error& e) {
      std::printf("%-14s unavailable: %s\n", name.c_str(), e.what());
    }
  }
  return 0;
}

int scenes_generate(const CommonOptions& o, const std::string& scene,
                    const std::vector<std::string>& sets, const std::string& out_dir) {
  const auto dir = o.scenes_dir.empty() ? default_scenes_dir() : std::filesystem::path(o.scenes_dir);
  const Scene s = open_scene(scene, dir, parse_overrides(sets));
  write_obj_sequence(*s.source, out_dir);
  std::printf("wrote %u frames of %s (%zu triangles) to %s\n", s.source->num_frames(), s.name.c_str(),
              s.source->topology().faces.size(), out_dir.c_str());
  return 0;
}

int scenes_info(const CommonOptions& o, const std::string& scene, const std::vector<std::string>& sets) {
  const auto dir = o.scenes_dir.empty() ? default_scenes_dir() : std::filesystem::path(o.scenes_dir);
  const Scene s = open_scene(scene, dir, parse_overrides(sets));
  const Topology& topo = s.source->topology();
  std::printf("scene       %s\n", s.name.c_str());
  std::printf("            %s\n", s.description.c_str());
  std::printf("triangles   %zu\nvertices    %u\nframes      %u\n", topo.faces.size(), topo.num_vertices,
              s.source->num_frames());
  for (const auto& ob : topo.objects)
    std::printf("object      %-10s faces %u..%u  %s\n", ob.name.c_str(), ob.first_face,
                ob.first_face + ob.num_faces, ob.rigid ? "rigid" : "deformable");
  if (!topo.queries.declared) {
    std::printf("queries     every overlapping pair\n");
  } else {
    for (uint32_t o : topo.queries.self) std::printf("query       self %s\n", topo.objects[o].name.c_str());
    for (const auto& [a, b] : topo.queries.inter)
      std::printf("query       inter %s - %s\n", topo.objects[a].name.c_str(), topo.objects[b].name.c_str());
  }
  if (s.source->num_frames() > 0) {
    std::vector<vec3d> first;
    s.source->positions(0, first);
    const FloatSpacing fs = float_spacing(topo, first, {0, 0, 0});
    std::printf("precision   median edge %.4g, float spacing %.4g at the largest coordinate %.6g%s\n", fs.median_edge,
                fs.spacing, fs.largest, fs.too_coarse() ? ": too coarse for fp32 (use --box-precision fp64)" : "");
  }
  std::vector<vec3d> v, prev;
  for (uint32_t f = 0; f < s.source->num_frames(); ++f) {
    s.source->positions(f, v);
    vec3d lo = v.empty() ? vec3d{} : v[0], hi = lo;
    double max_move = 0, sum_move = 0;
    for (size_t k = 0; k < v.size(); ++k) {
      lo = {std::min(lo.x, v[k].x), std::min(lo.y, v[k].y), std::min(lo.z, v[k].z)};
      hi = {std::max(hi.x, v[k].x), std::max(hi.y, v[k].y), std::max(hi.z, v[k].z)};
      if (!prev.empty()) {
        const double dx = v[k].x - prev[k].x, dy = v[k].y - prev[k].y, dz = v[k].z - prev[k].z;
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        max_move = std::max(max_move, d);
        sum_move += d;
      }
    }
    std::printf("frame %4u  box [%.4g %.4g %.4g]..[%.4g %.4g %.4g]", f, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    if (!prev.empty() && !v.empty())
      std::printf("  vertex motion mean %.4g max %.4g", sum_move / double(v.size()), max_move);
    std::printf("\n");
    prev = v;
  }
  return 0;
}

struct SweepOptions {
  std::string file, out_dir, scenes_dir;
  SlurmOptions slurm;
  int gpus = 0;  // 0: one per visible GPU, at least one cell at a time
  bool dry_run = false;
};

int sweep_command(const SweepOptions& w, const CLI::App& run) {
  std::vector<RunOptionInfo> run_options;
  for (const CLI::Option* opt : run.get_options())
    if (!opt->get_lnames().empty()) run_options.push_back({opt->get_lnames()[0], opt->get_expected_max() == 0});
  // The sweep file is the sweep's command line: its errors are usage errors.
  const SweepPlan plan = [&] {
    try {
      return load_sweep(w.file, run_options, pipeline_names());
    } catch (const Error& e) {
      fail_usage(e.what());
    }
  }();
  SweepRunOptions options;
  options.out_dir = w.out_dir;
  options.scenes_dir = w.scenes_dir.empty() ? "" : std::filesystem::absolute(w.scenes_dir).string();
  if (w.dry_run) {
    list_cells(plan, options);
    return 0;
  }
  if (!w.slurm.script.empty()) return slurm_script_command(plan, options, w.slurm);
  const int gpus = w.gpus > 0 ? w.gpus : cuda_device_info().device_count;
  options.slots = unsigned(std::max(gpus, 1));
  options.one_gpu_each = gpus > 0;
  return run_sweep(plan, options);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cdbench: GPU broad-phase collision detection benchmark for deforming meshes"};
  app.require_subcommand(1);
  app.set_version_flag("--version", version_text());
  CommonOptions o;

  auto* run = app.add_subcommand("run", "run pipelines on a scene and print timings");
  RunOptions r;
  run->add_option("--pipeline", r.pipeline,
                  "one of " + pipeline_list() + "; or several, comma-separated, run one after the other on the same frames")
      ->group(kPipelineGroup)
      ->capture_default_str();
  add_common(run, o);
  add_restructure(run, o);
  run->add_option("--check", r.check,
                  "compare frames with the exact CPU oracle: every, N (every N-th frame) or off; "
                  "recall, precision, missed and false positives per checked frame, and true contacts among the reported "
                  "pairs (exact triangle test), outside the timing")
      ->group(kAccuracyGroup)
      ->capture_default_str();
  run->add_option("--contact-distance", r.contact_distance,
                  "--check: contacts are reported pairs whose triangles lie within this distance (scene units, "
                  "exact test; 0: intersecting)")
      ->group(kAccuracyGroup)
      ->capture_default_str();
  run->add_option("--contact-substeps", r.contact_substeps,
                  "--check: the interval from the previous frame is sampled at this many substeps (linear "
                  "motion, both frames included) to count the contacts discrete boxes miss; a lower bound")
      ->group(kAccuracyGroup)
      ->capture_default_str();
  run->add_option("--warmup", r.warmup, "frames left out of the summary statistics")
      ->group(kMeasurementGroup)
      ->capture_default_str();
  run->add_option("--repeat", r.repeat,
                  "passes over the frames, each from a fresh state; times are the per-frame mean, "
                  "with the relative standard deviation reported as noise; Ctrl-C keeps the finished passes")
      ->group(kMeasurementGroup)
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  run->add_option("--max-noise", r.max_noise,
                  "stop repeating once the passes' mean frame times agree within this many percent (0: all passes)")
      ->group(kMeasurementGroup)
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  run->add_flag("--cold", r.cold, "flush the device's last-level cache before every frame (outside its timing)")
      ->group(kMeasurementGroup);
  auto* out_option = run->add_option(
      "--out", r.out, "write the results to this HDF5 file (docs/results-format.md); {pipeline} in the name is replaced")
      ->group(kOutputGroup);
  run->add_flag("--save-pairs", r.save_pairs, "also store each frame's sorted pairs in the results file")
      ->group(kOutputGroup)
      ->needs(out_option);
  run->add_flag("--quiet", r.quiet,
                "no per-frame lines and no list of the buffers that grew (the summary keeps their count); no "
                "progress lines when stderr is not a terminal")
      ->group(kOutputGroup);
  add_tuning(run, o);

  auto* verify = app.add_subcommand("verify", "compare pipelines with the exact oracle, frame by frame");
  std::vector<std::string> pipelines;
  size_t brute_limit = 30000;
  verify->add_option("--pipelines", pipelines, "pipelines to check (default: all)")->group(kPipelineGroup);
  add_common(verify, o);
  add_restructure(verify, o);
  verify->add_option("--brute-limit", brute_limit,
                     "largest triangle count for the O(N^2) oracle; above it, CPU sort-and-sweep")
      ->group(kAccuracyGroup)
      ->capture_default_str();
  add_tuning(verify, o);
  auto* scenes = app.add_subcommand("scenes", "list, describe and generate scenes");
  scenes->add_option("--scenes-dir", o.scenes_dir, "where named scenes live");
  auto* list = scenes->add_subcommand("list", "list scenes with sizes");
  std::string scene_name, generate_out;
  std::vector<std::string> scene_sets;
  auto* info = scenes->add_subcommand("info", "a scene's size, bounding box and motion per frame");
  info->add_option("scene", scene_name, "scene name, .json descriptor or mesh directory")->required();
  info->add_option("--set", scene_sets, "override a generator parameter: key=value (repeatable)");
  auto* generate = scenes->add_subcommand("generate", "write a scene's frames as OBJ files");
  generate->add_option("scene", scene_name, "scene name or .json descriptor")->required();
  generate->add_option("--set", scene_sets, "override a generator parameter: key=value, e.g. res=128 frames=10");
  generate->add_option("--out", generate_out, "output directory (frame_0000.obj, ...)")->required();
  scenes->require_subcommand(1);

  auto* report = app.add_subcommand("report", "summarize results files as a Markdown (or CSV) table");
  std::vector<std::string> report_files;
  bool csv = false;
  report->add_option("files", report_files,
                     "results files written by run --out, or directories: every .h5 under them, and the sweep cells that left none")
      ->required();
  report->add_flag("--csv", csv, "CSV instead of Markdown");

  auto* sweep = app.add_subcommand("sweep", "run the cells of a sweep file, one process each (docs/sweeps.md)");
  SweepOptions w;
  sweep->add_option("file", w.file, "sweep file (.json)")->required();
  sweep->add_option("--out", w.out_dir, "directory for the cells' results files, logs and status")->required();
  sweep->add_option("--gpus", w.gpus,
                    "cells at a time, one GPU each (CUDA_VISIBLE_DEVICES); default: the GPUs visible, 1 without")
      ->check(CLI::PositiveNumber);
  add_slurm_options(*sweep, w.slurm);
  sweep->add_flag("--dry-run", w.dry_run, "list the cells, their state and command lines; run nothing");
  sweep->add_option("--scenes-dir", w.scenes_dir, "where named scenes live, passed on to every cell");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version end here with 0; every parse error is a usage error.
    return app.exit(e) == 0 ? kExitOk : kExitUsage;
  }
  try {
    if (*run) return run_command(o, r, options_json(*run));
    if (*verify) return verify_command(o, pipelines, brute_limit);
    if (*list) return scenes_list(o);
    if (*info) return scenes_info(o, scene_name, scene_sets);
    if (*generate) return scenes_generate(o, scene_name, scene_sets, generate_out);
    if (*report) return print_results_table(report_files, csv);
    if (*sweep) return sweep_command(w, *run);
  } catch (const UsageError& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: error: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fflush(stdout);
    std::fprintf(stderr, "cdbench: error: %s\n", e.what());
    return kExitFailure;
  }
  return kExitOk;
}
