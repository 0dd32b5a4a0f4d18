#include "run_command.h"
#include "path_checks.h"
#include "exit_codes.h"
#include "number_checks.h"

#include <algorithm>
#include <unistd.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <string_view>
#include <vector>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/build_info.h"
#include "cdbench/core/error.h"
#include "frame_range.h"
#include "interrupt.h"
#include "cdbench/geometry/cached_frames.h"
#include "cdbench/geometry/float_spacing.h"
#include "cdbench/geometry/hashed_frames.h"
#include "harness/plans/plan_source.h"
#include "harness/results/gpu_attributes.h"
#include "harness/results/results_file.h"
#include "scenes/load/scene_label.h"
#include "harness/measure/noise_check.h"
#include "output_path.h"
#include "harness/results/config_json.h"
#include "cdbench/pipeline/device_probe.h"
#include "progress.h"
#include "report.h"
#include "run_loop.h"
#include "option_scope.h"
#include "option_table.h"
#include "registry/pipeline_kinds.h"

namespace cdb {
namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos)
      return line.substr(line.find_first_not_of(" \t", line.find(':') + 1));
  return "unknown cpu";
}

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

// The input --scene names, as an absolute path: the directory or .json descriptor given, or
// the named scene's descriptor in the scenes directory (the order io/scene.cpp resolves
// them in).
std::string input_path(const std::string& spec, const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  const fs::path p(spec);
  std::error_code ec;
  const fs::path chosen = fs::is_directory(p) || p.extension() == ".json" ? p : dir / (spec + ".json");
  const fs::path absolute = fs::absolute(chosen, ec);
  return (ec ? chosen : absolute).lexically_normal().string();
}

// --json: while it lives, what the commands print on stdout goes to stderr, so stdout
// carries the JSON summary alone (a pipe into a JSON reader needs nothing else there).
class StdoutToStderr {
 public:
  StdoutToStderr() {
    std::fflush(stdout);
    saved_ = dup(STDOUT_FILENO);
    if (saved_ < 0 || dup2(STDERR_FILENO, STDOUT_FILENO) < 0) fail("--json: cannot redirect stdout to stderr");
  }
  ~StdoutToStderr() {
    std::fflush(stdout);
    dup2(saved_, STDOUT_FILENO);
    close(saved_);
  }
  StdoutToStderr(const StdoutToStderr&) = delete;
  StdoutToStderr& operator=(const StdoutToStderr&) = delete;

 private:
  int saved_ = -1;
};

// The GPU's conditions around the measured passes, under the results file's attribute
// names (harness/results/gpu_attributes.h); a number not read is null.
nlohmann::json gpu_json(const GpuConditions& gpu) {
  nlohmann::json j = nlohmann::json::object();
  for (const GpuAttribute& a : gpu_attributes()) {
    const double x = a.text ? 0.0 : a.number(gpu);
    j[a.name] = a.text ? nlohmann::json(a.words(gpu)) : std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
  }
  return j;
}

// One pipeline's entry of run --json.
nlohmann::json run_json(const Scene& scene, const RunOptions& r, const std::string& pipeline,
                        const std::string& device, FrameRange range, const RunResult& res, const std::string& out) {
  const RunSummary& s = res.summary;
  const auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr); };
  return {{"scene", scene.name},
          {"scene_label", scene_label(scene.name, scene.overrides)},
          {"label", r.label},
          {"pipeline", pipeline},
          {"device", device},
          {"frame_first", range.first},
          {"frame_last", range.last},
          {"frames_run", s.frames},
          {"frames_measured", s.total.count},
          {"warmup", s.warmup},
          {"mean_ms", number(s.total.mean)},
          {"median_ms", number(s.total.median)},
          {"p95_ms", number(s.total.p95)},
          {"min_ms", number(s.total.min)},
          {"repeats", s.repeats},
          // In percent, as report and --max-noise give it; with one pass there is none.
          {"noise_pct", s.repeats > 1 ? number(100.0 * s.noise_median) : nlohmann::json(nullptr)},
          {"noise_warning", res.noise_warning},
          {"conditions", res.poor_conditions.empty() ? "good" : "poor"},
          {"conditions_notes", res.poor_conditions},
          {"gpu", gpu_json(res.gpu)},
          {"pairs_mean", number(s.pairs_mean)},
          {"pairs_by_query", s.by_query ? nlohmann::json{{"self_mean", number(s.pairs_self_mean)},
                                                         {"inter_mean", number(s.pairs_inter_mean)}}
                                        : nlohmann::json(nullptr)},
          {"peak_bytes", res.memory.peak_bytes},
          {"commit", build_info().git_sha},
          {"input_hash", res.input_hash},
          {"out", out.empty() ? nlohmann::json(nullptr) : nlohmann::json(out)}};
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
  run.label = r.label;
  run.input_path = input_path(o.scene, scenes_dir(o.scenes_dir));
  run.backend = config.device;
  run.device_name = gpu ? info.name : cpu_model() + " (" + std::to_string(omp_threads()) + " OpenMP threads)";
  run.cpu_model = cpu_model();
  run.omp_threads = uint64_t(omp_threads());
  run.driver_version = info.driver_version;
  run.runtime_version = info.runtime_version;
  run.warmup = r.loop.measuring.warmup;
  run.frame_first = range.first;
  run.frame_last = range.last;
  run.triangles = scene.source->topology().faces.size();
  run.vertices = scene.source->topology().num_vertices;
  run.cold = r.loop.measuring.cold;
  run.precision = box_precision_name(config.boxes.precision);
  run.contact_distance = double(float(r.contact_distance));
  run.contact_substeps = r.contact_substeps;
  run.repeat_plan = repeat_plan_name(r.loop.measuring.repeat_plan);
  run.phase_timing = config.launch.phase_timing;
  // identity_options: the options compare matches runs on, as this build has them, so the
  // scripts match runs as compare does without a copy of the list (docs/results-format.md).
  run.params_json = nlohmann::json{{"command", "run"},
                                   {"options", cli_options},
                                   {"identity_options", identity_options()},
                                   {"pipeline_config", to_json(config)},
                                   {"resolved",
                                    {{"device", config.device},
                                     {"scene", scene.name},
                                     {"scenes_dir", scenes_dir(o.scenes_dir).string()},
                                     {"frame_first", range.first},
                                     {"frame_last", range.last},
                                     {"warmup", run.warmup},
                                     {"warmup_ms", r.loop.measuring.warmup_ms},
                                     {"repeat", r.loop.measuring.repeat},
                                     {"repeat_plan", repeat_plan_name(r.loop.measuring.repeat_plan)},
                                     {"max_noise", r.loop.measuring.max_noise_pct},
                                     {"cold", run.cold},
                                     {"contact_distance", run.contact_distance},
                                     {"contact_substeps", run.contact_substeps}}}}
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

// --out with every {pipeline} replaced by the pipeline's name.
std::string results_path(const std::string& pattern, const std::string& pipeline) {
  static constexpr std::string_view placeholder = "{pipeline}";
  std::string path = pattern;
  for (size_t at = path.find(placeholder); at != std::string::npos; at = path.find(placeholder, at + pipeline.size()))
    path.replace(at, placeholder.size(), pipeline);
  return path;
}

// The results file of each pipeline, checked before any work: two pipelines writing the
// same file (--pipeline c,c) would leave one run's results, and an existing file is kept
// unless --overwrite. Per pipeline: whether its file exists (and is then replaced only once
// the new run completes), and the lock that keeps other runs off it while this one lives.
std::vector<OutputClaim> check_results_paths(const RunOptions& r, const std::vector<std::string>& names) {
  std::vector<OutputClaim> existing;
  if (r.out.empty()) return existing;
  std::vector<std::string> seen;
  for (const auto& name : names) {
    const std::string path = results_path(r.out, name);
    const std::string normal = std::filesystem::path(path).lexically_normal().string();
    for (size_t k = 0; k < seen.size(); ++k)
      if (seen[k] == normal)
        fail_usage("--out " + r.out + ": pipelines " + names[k] + " and " + name + " would both write " + path +
                   " (each pipeline needs its own file; name a pipeline once)");
    seen.push_back(normal);
  }
  for (const auto& name : names) existing.push_back(check_output_path(results_path(r.out, name), r.overwrite));
  return existing;
}

using PlanOfPipeline = std::vector<std::shared_ptr<const RecordedPlan>>;

// --front-cycle FILE: each pipeline's recorded plan, {pipeline} in FILE replaced by its
// name; none where --front-cycle is auto or K. A plan that cannot be read is a usage error.
PlanOfPipeline load_plans(const CommonOptions& o, const std::vector<std::string>& names) {
  PlanOfPipeline plans(names.size());
  if (o.front_plan.empty()) return plans;
  for (size_t p = 0; p < names.size(); ++p) {
    try {
      plans[p] = std::make_shared<const RecordedPlan>(load_plan(results_path(o.front_plan, names[p]), names[p]));
    } catch (const Error& e) {
      fail_usage(std::string("--front-cycle: ") + e.what());
    }
  }
  return plans;
}

// Each pipeline gets its plan to replay; one it cannot replay (another pipeline's
// restructures, a pipeline without fronts) is a usage error.
void give_plans(const std::vector<std::unique_ptr<Pipeline>>& pipelines, const PlanOfPipeline& plans,
                const std::vector<std::string>& names) {
  for (size_t p = 0; p < pipelines.size(); ++p) {
    if (!plans[p]) continue;
    bool replays = false;
    try {
      replays = pipelines[p]->replay_plan(plans[p]);
    } catch (const Error& e) {
      fail_usage(std::string("--front-cycle: ") + e.what());
    }
    if (!replays)
      fail_usage("--front-cycle " + plans[p]->source + ": pipeline " + names[p] +
                 " has no front plan to replay (only the front pipelines have one)");
  }
}

}  // namespace

void check_run_options(const CommonOptions& o, const RunOptions& r, const std::string& device) {
  const std::vector<std::string> names = split_pipelines(r.pipeline);
  contact_check(r, check_interval(r.check));
  if (names.size() > 1 && !r.out.empty() && r.out.find("{pipeline}") == std::string::npos)
    fail_usage("--out " + r.out + ": several pipelines need {pipeline} in the file name");
  // Its form only: the scene, not loaded here, says how many frames there are.
  parse_frame_range(o.frames, UINT32_MAX);
  const PlanOfPipeline plans = load_plans(o, names);
  if (device == "cpu") give_plans(make_pipelines(o, names, device), plans, names);
}

CLI::App* add_run_command(CLI::App& app, CommonOptions& o, RunOptions& r) {
  auto* run = app.add_subcommand("run", "run pipelines on a scene and print timings");
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
  run->add_option("--warmup", r.loop.measuring.warmup, "frames left out of the summary statistics")
      ->group(kMeasurementGroup)
      ->capture_default_str();
  run->add_option("--warmup-ms", r.loop.measuring.warmup_ms,
                  "before the measured passes, frames run untimed from the first (again from the first after "
                  "the last) for at least this long, then the pipeline starts afresh; a process's first pass "
                  "otherwise runs slower (0: none; the default is CDBENCH_WARMUP_MS where set, as the tests set it)")
      ->group(kMeasurementGroup)
      ->envname("CDBENCH_WARMUP_MS")
      ->check(finite_at_least(0))
      ->capture_default_str();
  run->add_option("--repeat", r.loop.measuring.repeat,
                  "passes over the frames, each from a fresh state; times are the per-frame mean, "
                  "with the relative standard deviation reported as noise; Ctrl-C keeps the finished passes")
      ->group(kMeasurementGroup)
      ->check(whole_in(1, UINT32_MAX))
      ->capture_default_str();
  add_choice<RepeatPlan>(
      run, "--repeat-plan", r.loop.measuring.repeat_plan,
      "front pipelines under --repeat: replay: the first pass plans (as --front-cycle says) and every later pass "
      "replays its recorded plan, so each frame's mean is over the same operations; free: every pass plans for "
      "itself, and frames whose passes ran different operations are marked (op shows them joined by |) and counted",
      {"replay", "free"}, [](const std::string& w) { return w == "free" ? RepeatPlan::free : RepeatPlan::replay; },
      repeat_plan_name(r.loop.measuring.repeat_plan))
      ->group(kMeasurementGroup);
  run->add_option("--max-noise", r.loop.measuring.max_noise_pct,
                  "stop repeating once the passes' mean frame times agree within this many percent (0: all passes)")
      ->group(kMeasurementGroup)
      ->check(finite_at_least(0))
      ->capture_default_str();
  run->add_flag("--cold", r.loop.measuring.cold, "flush the device's last-level cache before every frame (outside its timing)")
      ->group(kMeasurementGroup);
  run->add_option("--load-window-ms", r.loop.measuring.load_window_ms,
                  "the span over which the host's load is sampled, before the run and after each pipeline's "
                  "measured frames, to flag a run on a busy host (0: not sampled, recorded as absent; the default "
                  "is CDBENCH_LOAD_WINDOW_MS where set, as the tests set it)")
      ->group(kMeasurementGroup)
      ->envname("CDBENCH_LOAD_WINDOW_MS")
      ->check(finite_at_least(0))
      ->capture_default_str();
  add_measurement(run, o);
  auto* out_option = run->add_option(
      "--out", r.out, "write the results to this HDF5 file (docs/results-format.md); {pipeline} in the name is replaced")
      ->check(non_empty_path())
      ->group(kOutputGroup);
  run->add_flag("--overwrite", r.overwrite,
                "let --out replace an existing file; it is replaced only once the new run completes (until then the "
                "new file is NAME.incomplete beside it)")
      ->group(kOutputGroup)
      ->needs(out_option);
  run->add_flag("--save-pairs", r.loop.measuring.save_pairs, "also store each frame's sorted pairs in the results file")
      ->group(kOutputGroup)
      ->needs(out_option);
  run->add_option("--label", r.label,
                  "a name for the run, stored in the results file and shown by report and compare (e.g. a "
                  "branch or a machine)")
      ->group(kOutputGroup);
  run->add_flag("--json", r.json,
                "print a JSON summary of each pipeline's run on stdout at the end; the human output goes to "
                "stderr instead")
      ->group(kOutputGroup);
  run->add_flag("--quiet", r.quiet,
                "no per-frame lines and no list of the buffers that grew (the summary keeps their count); no "
                "progress lines when stderr is not a terminal")
      ->group(kOutputGroup);
  add_tuning(run, o);
  run->footer(pipeline_table());
  return run;
}

int run_command(const CommonOptions& o, const RunOptions& r, const nlohmann::json& cli_options) {
  // Until the first results file is about to be made a signal ends the program at once;
  // from then on it is seen between frames and the file is closed as incomplete.
  InterruptScope interrupts(InterruptScope::Mode::exit_at_once);
  std::optional<StdoutToStderr> redirect;
  if (r.json) redirect.emplace();
  nlohmann::json runs = nlohmann::json::array();
  const std::string device = resolve_device(o.device);
  check_run_options(o, r, "");
  const std::vector<std::string> names = split_pipelines(r.pipeline);
  const ContactCheck contact = contact_check(r, check_interval(r.check));
  std::vector<std::unique_ptr<Pipeline>> pipelines = make_pipelines(o, names, device);
  const PlanOfPipeline plans = load_plans(o, names);
  give_plans(pipelines, plans, names);
  const std::vector<OutputClaim> existing = check_results_paths(r, names);
  print_environment(device);
  for (const std::string& line : ignored_option_warnings(o.given, names)) std::printf("warning: %s\n", line.c_str());
  const HostLoad load_before = sample_host_load(r.loop.measuring.load_window_ms);
  const std::string busy = host_load_warning(load_before, "before the run");
  if (!busy.empty()) std::printf("warning: %s\n", busy.c_str());
  // A stopped run's partial file, which its message pointed to, is where this run stages
  // its own: said, rather than lost without a word.
  for (size_t p = 0; p < existing.size(); ++p) {
    const std::string staged = results_path(r.out, names[p]) + ".incomplete";
    std::error_code ec;
    if (existing[p].existed && std::filesystem::exists(staged, ec))
      std::printf("warning: %s, the partial file an earlier run left, will be replaced by this run's\n",
                  staged.c_str());
  }
  Scene scene = load_scene(o);
  const Topology& topo = scene.source->topology();
  // A box's face is the box's diagonal (io/box_stream.h), so --check's exact triangle
  // contact counts would be counts of segments: refused rather than silently wrong.
  if (topo.box_faces && check_interval(r.check))
    fail_usage("--check " + r.check + ": scene " + scene.name + " has " + std::to_string(topo.box_faces) +
               " boxes (a box stream), and --check counts contacts of triangles; use `cdbench verify` to compare "
               "with the oracle");
  const FrameRange range = parse_frame_range(o.frames, scene.source->num_frames());
  for (const auto& plan : plans) {
    if (!plan) continue;
    try {
      check_plan_frames(*plan, range.first, range.last);
    } catch (const Error& e) {
      fail_usage(std::string("--front-cycle: ") + e.what());
    }
  }
  std::printf("scene: %s — %s\n       %zu triangles, %u vertices, frames %u:%u\n",
              scene.name.c_str(), scene.description.c_str(), topo.faces.size(),
              topo.num_vertices, range.first, range.last);
  const bool fp64 = o.config.boxes.precision == BoxPrecision::fp64;
  const std::string spacing_warning =
      range.last > range.first ? float_spacing_warning(*scene.source, range.first, fp64) : "";
  if (!spacing_warning.empty()) std::printf("warning: %s\n", spacing_warning.c_str());
  const std::string short_warning = warmup_warning(range, r.loop.measuring.warmup, o.frames);
  if (!short_warning.empty()) std::printf("warning: %s\n", short_warning.c_str());
  // Measured once, before any frame: the yardstick of the bandwidth floor; and the cache
  // flush of --cold, allocated here rather than in the frame loop.
  const std::unique_ptr<DeviceProbe> probe = make_device_probe(device);
  if (r.loop.measuring.cold) probe->reserve_cache_flush();
  const double copy_gbps = probe->copy_bandwidth_gbps();
  std::printf("copy bandwidth: %.0f GB/s (%s, measured; read + written)\n", copy_gbps, device.c_str());
  std::unique_ptr<FrameSource> cached;
  if (names.size() > 1 || r.loop.measuring.repeat > 1) cached = std::make_unique<CachedFrames>(*scene.source);
  // Above the cache: each frame is hashed once, as it is first loaded.
  const HashedFrames frames(cached ? *cached : *scene.source);
  interrupts.defer();
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
    if (const int signal = interrupts.signal()) {
      // Between pipelines: the next one's file is not made at all.
      std::fflush(stdout);
      std::fprintf(stderr, "cdbench: interrupted by %s before pipeline %s\n", signal_name(signal), name.c_str());
      return exit_for_signal(signal);
    }
    std::optional<ResultsFile> out;
    if (!one.out.empty()) {
      RunInfo info = run_info(o, one, scene, config, range, cli_options);
      info.plan_source = plans[p] ? plans[p]->source : "";
      info.copy_gbps = copy_gbps;
      info.precision_warning = spacing_warning;
      info.host_busy_before = load_before.busy_share;
      info.host_cores = uint64_t(std::max(0L, load_before.cores));
      info.host_warning = busy;
      out.emplace(one.out, info, existing[p].existed ? ResultsFile::Placement::staged : ResultsFile::Placement::in_place);
    }
    RunLoopOptions loop = r.loop;
    loop.measuring.frames_kept = cached != nullptr;
    loop.measuring.plan_source = plans[p] ? plans[p]->source : "";
    loop.frame_lines = !r.quiet;
    loop.list_growth = !r.quiet;
    loop.progress = Progress::mode_for(r.quiet);
    loop.measuring.check_every = check_interval(r.check);
    loop.measuring.probe = probe.get();
    loop.copy_gbps = copy_gbps;
    loop.measuring.host_before = load_before;
    loop.measuring.oracle = [&topo, &config](const std::vector<vec3d>& v) {
      return sweep_oracle_pairs(topo, v, config.skip_adjacent);
    };
    loop.measuring.faces = &topo.faces;
    loop.measuring.contact = contact;
    if (!config_conservative(config))
      loop.accuracy_warning = "--refit-every " + std::to_string(config.tree.refit_every) +
                              " keeps stale boxes between refits: NOT conservative, pairs can be missed";
    loop.measuring.input_hash = [&frames, range] {
      const std::optional<uint64_t> h = frames.input_hash(range.first, range.last);
      return h ? hash_hex(*h) : std::string();
    };
    RunResult result;
    if (const int rc = run_frames(*pipeline, frames, range, out ? &*out : nullptr, interrupts, loop, &result)) return rc;
    runs.push_back(run_json(scene, r, name, device, range, result, one.out));
  }
  if (redirect) {
    redirect.reset();
    std::printf("%s\n", nlohmann::json{{"command", "run"}, {"runs", runs}}.dump(2).c_str());
  }
  return kExitOk;
}

}  // namespace cdb
