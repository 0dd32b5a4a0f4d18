#include "options.h"
#include "join_words.h"
#include "path_checks.h"
#include "number_checks.h"

#include <cstdio>
#include <functional>

#include "cdbench/core/build_info.h"
#include "cdbench/core/error.h"
#include "cdbench/geometry/mesh_pieces.h"
#include "scenes/load/scene_label.h"
#include "cdbench/pipeline/device_probe.h"
#include "registry/pipeline_kinds.h"
#include "report.h"

namespace cdb {
namespace {

// An on/off option into a bool; CLI11 reads on as true and off as false. Typed TEXT in the
// help, as the word it takes.
CLI::Option* add_switch(CLI::App* cmd, const std::string& name, bool& field, const std::string& help) {
  return cmd->add_option(name, field, help)
      ->check(CLI::IsMember({"on", "off"}))
      ->type_name("TEXT")
      ->default_str(field ? "on" : "off");
}

}  // namespace

void add_common(CLI::App* cmd, CommonOptions& o) {
  PipelineConfig& c = o.config;
  cmd->add_option("--scene", o.scene, "scene name, .json descriptor, or directory of mesh frames")
      ->check(non_empty_path())
      ->group(kSceneGroup)
      ->capture_default_str();
  cmd->add_option("--device", o.device, "cuda, cpu, or auto (cuda when a GPU is present)")
      ->group(kPipelineGroup)
      ->check(CLI::IsMember({"auto", "cuda", "cpu"}))
      ->capture_default_str();
  cmd->add_option("--set", o.sets, "override a generator parameter of a procedural scene: key=value (repeatable)")
      ->group(kSceneGroup);
  cmd->add_option("--frames", o.frames,
                  "frames to run: A:B is A to B-1 (half-open), A: is A to the last, A is frame A only "
                  "(--frames 3: frame 3 alone, not three frames); default all")
      ->group(kSceneGroup);
  cmd->add_option("--scenes-dir", o.scenes_dir, "where named scenes live")->group(kSceneGroup);
  cmd->add_option("--rebuild-every", c.tree.rebuild_every,
                  "bvh pipeline: rebuild every K frames (0: build on the first frame only)")
      ->group(kPipelineGroup)
      ->capture_default_str();
  // auto and K are cycles; anything else names a recorded plan, read once the pipelines
  // are known (run_command.cpp).
  cmd->add_option_function<std::string>(
         "--front-cycle",
         [&c, &o](const std::string& v) {
           const bool cycle = v == "auto" || v.find_first_not_of("0123456789") == std::string::npos;
           o.front_plan = cycle ? "" : v;
           c.fronts.cycle = v == "auto" || !cycle ? 0u : uint32_t(std::stoul(v));
         },
         "front pipelines: when fronts are updated instead of preserved; auto: once the measured growth of "
         "the steady frames' cost since the last update has paid for one (rent or buy); K: every K-th frame "
         "since the fronts were generated (the paper's fixed cycle); FILE: replay a recorded plan, every "
         "frame's build or refit and front operations as recorded: a plan file, or a results file "
         "FILE.h5[:PIPELINE[:PASS]] (its pipeline's, or PIPELINE's, pass 0 or PASS); {pipeline} in FILE is "
         "replaced by each pipeline's name (docs/usage.md \"Plans\"); FILE on run only, verify takes auto and K")
      ->check(CLI::Validator(
          [](std::string& v) -> std::string {
            if (v == "auto" || (!v.empty() && v.find_first_not_of("0123456789") != std::string::npos)) return "";
            const bool positive = !v.empty() && v.size() < 10 && std::stoul(v) > 0;
            return positive ? "" : "auto, a positive whole number of frames or a plan file, not '" + v + "'";
          },
          "auto|K|FILE"))
      ->default_str(c.fronts.cycle ? std::to_string(c.fronts.cycle) : "auto");
  cmd->add_flag("--skip-adjacent", c.skip_adjacent,
                "co-vertex filtering: do not report pairs of triangles that share a vertex (oracle too)")
      ->group(kAccuracyGroup);
  cmd->add_option("--box-margin", c.boxes.margin,
                  "fat boxes: inflate every triangle box by this much (scene units) on each side; conservative "
                  "(recall stays 1 against the exact oracle, precision drops); all pipelines")
      ->group(kAccuracyGroup)
      ->check(finite_at_least(0))
      ->capture_default_str();
  add_choice<bool>(
      cmd, "--boxes", c.boxes.swept,
      "discrete: each triangle's box at the frame; swept: its box over the frame interval (previous and current "
      "positions); swept is conservative with respect to the discrete oracle; all pipelines",
      {"discrete", "swept"}, [](const std::string& w) { return w == "swept"; }, c.boxes.swept ? "swept" : "discrete")
      ->group(kAccuracyGroup);
  add_choice<BoxPrecision>(
      cmd, "--box-precision", c.boxes.precision,
      "fp32: the boxes of the positions rounded to float; fp64: the positions rebased on the first frame's centre in "
      "double before rounding, for scenes far from the origin (a run warns when fp32 cannot hold a scene); q16: fp32 "
      "boxes snapped outward onto a 16-bit grid per axis over the frame's vertex bounds, as a 16-bit box format stores "
      "them; all conservative against the double geometry (recall stays 1, precision drops); all pipelines",
      {"fp32", "fp64", "q16"}, parse_box_precision, box_precision_name(c.boxes.precision))
      ->group(kAccuracyGroup);
  cmd->add_option("--refit-every", c.tree.refit_every,
                  "NOT CONSERVATIVE: front pipelines and bvh refit the hierarchy only every K frames and keep stale "
                  "boxes in between, so pairs can be missed (recall < 1 under --check); sweep, hash, grid, brute and "
                  "example-sap ignore it; 1: every frame")
      ->group(kAccuracyGroup)
      ->check(whole_in(1, UINT32_MAX))
      ->capture_default_str();
  // --front-cycle is declared above with the other pipeline options; its heading:
  cmd->get_option("--front-cycle")->group(kPipelineGroup);
}

void add_measurement(CLI::App* cmd, CommonOptions& o) {
  add_switch(cmd, "--phase-timing", o.config.launch.phase_timing,
             "time each phase of a frame with events; off: only the frame and its upload (no event between "
             "kernels, which in a CUDA graph costs a node and keeps the next kernel from launching early)")
      ->group(kMeasurementGroup);
}

// The defaults were tuned on the H100 (sm_90); where a default depends on the GPU the help says so.
void add_tuning(CLI::App* cmd, CommonOptions& o) {
  PipelineConfig& c = o.config;
  // MortonBits' values are the widths, so CLI11 reads the checked number into the enum.
  cmd->add_option("--morton-bits", c.tree.morton_bits, "Morton code width (all devices)")
      ->group(kTuningGroup)
      ->check(CLI::IsMember({30, 63}))
      ->type_name("INT")
      ->capture_default_str();
  add_switch(cmd, "--cuda-graph", c.launch.cuda_graph,
             "front pipelines on cuda: capture the steady-state frame (refit + preserve) in a CUDA graph once "
             "and replay it while its launches stay the same; off (the default, measured on the H100): plain "
             "launches every frame")
      ->group(kTuningGroup);
  add_switch(cmd, "--dependent-launch", c.launch.dependent_launch,
             "cuda: launch every kernel with programmatic stream serialization, so it is scheduled while the "
             "kernel before it runs and waits for it on the device; off: plain launches. Per architecture: "
             "a Hopper (sm_90) feature, the kernels' wait is compiled for sm_90 and later only; its effect "
             "on earlier GPUs is not measured")
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--preserve-warp", c.fronts.preserve_warp,
      "front pipelines on cuda: preserve shares each front node's traversal with the idle lanes of its warp; auto: "
      "while the fronts fit in " + std::to_string(kWarpSharingWaves) +
          " waves of the GPU's resident threads (per architecture: SMs x threads per SM, read from the GPU at run time)",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.fronts.preserve_warp))
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--update-warp", c.fronts.update_warp,
      "front pipelines on cuda: the operations that write fronts (generate, update, restructure) share each "
      "traversal with the idle lanes of its warp; auto: as --preserve-warp",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.fronts.update_warp))
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--preserve-bound", c.fronts.preserve_bound,
      "front pipelines on cuda: launch preserve under a register bound (" + std::to_string(kPreserveMinBlocks) +
          " blocks an SM: more resident warps, fewer registers each); auto: while the fronts fill " +
          std::to_string(kPreserveBoundedWaves) + " waves of the GPU's resident threads",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.fronts.preserve_bound))
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--preserve-two-nodes", c.fronts.preserve_two_nodes,
      "front pipelines: each preserve thread takes two front nodes and gathers both nodes' boxes before it "
      "tests either (two sets of loads in flight, half the threads; no register bound); auto: on cuda while "
      "the fronts fill " +
          std::to_string(kPreserveTwoNodesWaves) + " waves of the GPU's resident threads",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.fronts.preserve_two_nodes))
      ->group(kTuningGroup);
  add_switch(cmd, "--order-updates", c.fronts.order_updates,
             "ordered front pipelines: histogram-sort the front each update produces (the paper); off: keep the "
             "update's output in its blocks' order and sort only generated and restructured fronts (b and c "
             "sort in their balance before the next update)")
      ->group(kTuningGroup);
  add_switch(cmd, "--update-in-place", c.fronts.update_in_place,
             "front pipelines: an update writes only the front nodes that change, into the current front (holes "
             "and an appended tail), and the update once those reach --compact-share of the front produces it "
             "whole and ordered; off: every update produces the whole front (the paper). Off measured as fast or "
             "faster under --front-cycle auto; on is faster when fronts update every frame")
      ->group(kTuningGroup);
  cmd->add_option("--compact-share", c.fronts.compact_share,
                  "front pipelines with --update-in-place: the share of a front's nodes changed in place (holes "
                  "plus appended nodes) at which the next update produces the front whole again")
      ->group(kTuningGroup)
      ->check(finite_at_least(0))
      ->capture_default_str();
  add_choice<AutoSwitch>(
      cmd, "--maintain-ahead", c.tree.maintain_ahead,
      "front pipelines that build ahead (--rebuild-ahead): on: each maintenance due (--front-cycle) is a rebuild "
      "built ahead instead of an update or generate in its frame (pipeline c then never inspects); off: "
      "maintenances run in their frames; auto: the first in its frame, the next built ahead, then each the way "
      "whose last cycle (the maintenance and the frames to the next) cost less per pair (measured no faster than off)",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.tree.maintain_ahead))
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--update-ahead", c.fronts.update_ahead,
      "front pipelines that build ahead (--rebuild-ahead): on: a due update of the fronts runs on the side stream "
      "(from the current fronts, against a copy of the tree's boxes) while the frames preserve, and the first frame "
      "that finds it done adopts the updated fronts (pipeline c then inspects nothing after it); off: updates run "
      "in their frames; auto: on",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.fronts.update_ahead))
      ->group(kTuningGroup);
  add_switch(cmd, "--rebuild-degraded", c.tree.rebuild_degraded,
             "front pipelines with --front-cycle auto: a maintenance rebuilds the tree and generates every front "
             "instead of updating once the rent the fronts paid on the tree since the build (the share of each "
             "steady frame by which they hold more nodes per pair than after it) reaches a rebuild's cost over an "
             "update's; off: only --rebuild-every and pipeline c's Formula 2 rebuild")
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--rebuild-ahead", c.tree.rebuild_ahead,
      "front pipelines: a rebuild after the first frame runs on a second, low-priority GPU stream (the new tree, "
      "its fronts' generate and ordering) while the frames preserve the current fronts, and the first frame that "
      "finds it done adopts it; off: the rebuilding frame builds and generates in the frame; auto: on with "
      "--device cuda, off on the cpu. Not on scenes split into two trees (--split-objects), the radix orderings or "
      "--refit-every above 1",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.tree.rebuild_ahead))
      ->group(kTuningGroup);
  add_choice<bool>(
      cmd, "--ahead-generate", c.tree.ahead_placed,
      "front pipelines that build ahead (--rebuild-ahead): how the fronts built or updated ahead are produced on "
      "the side stream. scatter: one generate or update into the produced arrays the current fronts lend, then the "
      "histogram sort's scatter into arrays of their own (three sets of front arrays at the peak); place: two, the "
      "first counting each tree node's front nodes, the second putting each at its sorted place straight into the "
      "lent arrays (two sets, as in a frame; the side's traversals run twice)",
      {"scatter", "place"}, [](const std::string& w) { return w == "place"; },
      c.tree.ahead_placed ? "place" : "scatter")
      ->group(kTuningGroup);
  add_choice<SplitRule>(
      cmd, "--split-objects", c.tree.split,
      "front pipelines and bvh on scenes with declared queries: rigid: a second tree takes the rigid objects; "
      "queries: also each deformable object that only inter queries with self-queried deformable objects name (an "
      "avatar under its cloth: its pairs come from one cross traversal, without a self front of its own), refitted "
      "and rebuilt with the first. rigid measured faster on the GPU where the cloth's own pairs dominate",
      {"rigid", "queries"}, parse_split_rule, split_rule_name(c.tree.split))
      ->group(kTuningGroup);
  cmd->add_option("--rebuild-growth", c.tree.rebuild_growth,
                  "front pipelines with --rebuild-degraded: a maintenance rebuilds where an update would make "
                  "fronts of more than this many times the nodes per pair a rebuild would (and got there fast; "
                  "docs/front-maintenance.md)")
      ->check(finite_at_least(1))
      ->capture_default_str()
      ->group(kTuningGroup);
  add_switch(cmd, "--regenerate", c.fronts.regenerate,
             "front pipelines with --front-cycle auto: each maintenance runs an update of the fronts or a generate "
             "of new ones, whichever measured cheaper per front node last (a generate is tried once the first "
             "frame's generate costs less than an update after the first); off: always an update (the paper)")
      ->group(kTuningGroup);
  add_switch(cmd, "--update-probe", c.fronts.update_probe,
             "front pipelines: the preserves before an update count what it can produce, and the front buffers "
             "grow to that between frames; off: an update that outgrows them grows them inside its frame and runs "
             "again")
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--refit-levels", c.tree.refit_levels,
      "front pipelines and bvh: the refit merges each tile's nodes level by level, deepest first, with a block "
      "barrier between levels; off: each leaf's thread climbs and the second to reach a node merges it; auto: on "
      "with --device cuda, off on the cpu",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.tree.refit_levels))
      ->group(kTuningGroup);
  add_choice<AutoSwitch>(
      cmd, "--build-pieces", c.tree.build_pieces,
      "front pipelines and bvh: a build keys each leaf by its connected piece first (faces sharing a vertex; 2 "
      "to 4096 pieces), placed by its first face, so every piece gets subtrees of its own and a refitted tree "
      "loosens only above the pieces as they move apart; off: plain Morton codes; auto: where the pieces average "
      "at least " + std::to_string(kPieceMinMeanFaces) + " faces (objects, not a soup of triangles or boxes)",
      {"auto", "on", "off"}, parse_auto_switch, auto_switch_name(c.tree.build_pieces))
      ->group(kTuningGroup);
  cmd->add_option("--refit-top-leaves", c.tree.refit_top_leaves,
                  "front pipelines and bvh: trees of up to this many leaves refit their top (the nodes whose leaves "
                  "span refit tiles) in one block of threads, larger trees hand it over between blocks; 0: always "
                  "hand over. The default was measured on the H100; other GPUs may want another")
      ->group(kTuningGroup)
      ->check(CLI::Range(0u, kRefitTopLeavesLimit))
      ->capture_default_str();
}

void add_restructure(CLI::App* cmd, CommonOptions& o) {
  PipelineConfig& c = o.config;
  cmd->add_option("--restructure-quality", c.restructure.quality,
                  "pipeline c: a subtree is degraded when its Q exceeds this times Q(root) after the last rebuild")
      ->group(kPipelineGroup)
      ->check(finite_at_least(0))
      ->capture_default_str();
  cmd->add_option("--restructure-min-leaves", c.restructure.min_leaves,
                  "pipeline c: smallest candidate subtree, in leaves")
      ->group(kPipelineGroup)
      ->check(CLI::Range(2u, 0x7FFFFFFFu))
      ->capture_default_str();
  cmd->add_option("--restructure-max-fraction", c.restructure.max_fraction,
                  "pipeline c: largest candidate subtree, as a share of all leaves")
      ->group(kPipelineGroup)
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--threshold-refit", c.restructure.threshold_refit,
                  "pipeline c, Formula 2: below this share of leaves in candidates, only refit")
      ->group(kPipelineGroup)
      ->check(finite_at_least(0))
      ->capture_default_str();
  cmd->add_option("--threshold-build", c.restructure.threshold_build,
                  "pipeline c, Formula 2: from this share of leaves in candidates on, rebuild instead of restructuring")
      ->group(kPipelineGroup)
      ->check(finite_at_least(0))
      ->capture_default_str();
  add_switch(cmd, "--restructure-price", c.restructure.priced,
             "pipeline c: restructure only where this run measured a restructure to save more on the frames "
             "after it than it costs, in time: the steady frames a restructure began against those an update alone "
             "began (before one was measured: where the last stretch's rent, in its candidates' share of the fronts, "
             "covers the update before it over a steady frame); off: wherever Formula 2 says (the paper)")
      ->group(kPipelineGroup);
}

std::string pipeline_list() { return join_words(pipeline_names(), ", "); }

std::string pipeline_table() {
  std::string table = "Pipelines:\n";
  for (const PipelineKind& k : pipeline_kinds()) {
    char name[32];
    std::snprintf(name, sizeof name, "  %-13s ", k.name);
    table += name + std::string(k.description) + (*k.paper ? std::string(" [paper: ") + k.paper + "]" : "") + "\n";
  }
  return table;
}

std::string resolve_device(const std::string& device) {
  if (device != "auto") return device;
  return cuda_device_info().available ? "cuda" : "cpu";
}

PipelineConfig make_config(const CommonOptions& o, const std::string& pipeline,
                           const std::string& device) {
  PipelineConfig c = o.config;
  c.name = pipeline;
  c.device = device;
  return c;
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

std::filesystem::path scenes_dir(const std::string& given) {
  return given.empty() ? default_scenes_dir() : std::filesystem::path(given);
}

Scene load_scene(const CommonOptions& o) {
  return open_scene(o.scene, scenes_dir(o.scenes_dir), parse_set_overrides(o.sets));
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

}  // namespace cdb
