#include "verify_command.h"
#include "path_checks.h"
#include "exit_codes.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cdbench/oracle/sweep_oracle.h"
#include "cdbench/core/error.h"
#include "frame_range.h"
#include "cdbench/geometry/margin_range.h"
#include "cdbench/geometry/position_rounding.h"
#include "harness/pairs/pairs_file.h"
#include "report.h"
#include "option_scope.h"
#include "registry/pipeline_kinds.h"

namespace cdb {
namespace {

// --pairs: each frame's file against the oracle's pairs; prints one line a frame (and the
// first few missed, extra and duplicated pairs of a mismatch) and keeps the totals.
class PairsCheck {
 public:
  PairsCheck(std::filesystem::path dir, std::vector<std::filesystem::path> files, uint32_t first_frame)
      : dir_(std::move(dir)), files_(std::move(files)), first_frame_(first_frame) {}

  void check_frame(uint32_t frame, uint32_t num_faces, const std::vector<PrimPair>& expected) {
    const std::filesystem::path& file = files_[frame - first_frame_];
    const std::string name = file.filename().string();
    PairsRead read;
    try {
      read = read_pairs_file(file, num_faces);
    } catch (const Error& e) {
      ++unreadable_;
      std::printf("  pairs frame %u %s: ERROR %s\n", frame, name.c_str(), e.what());
      return;
    }
    const PairSetDiff d = diff_pair_sets(expected, read.pairs);
    missed_ += d.missing_count;
    extra_ += d.unexpected_count;
    duplicates_ += read.duplicates;
    if (d.equal() && read.duplicates == 0) {
      std::printf("  pairs frame %u %s: exact, %llu pairs\n", frame, name.c_str(),
                  static_cast<unsigned long long>(expected.size()));
      return;
    }
    ++mismatched_;
    std::printf("  pairs frame %u %s: MISMATCH: oracle %llu pairs, file %llu listed; %llu missed, %llu extra, "
                "%llu duplicates\n",
                frame, name.c_str(), static_cast<unsigned long long>(expected.size()),
                static_cast<unsigned long long>(read.listed), static_cast<unsigned long long>(d.missing_count),
                static_cast<unsigned long long>(d.unexpected_count), static_cast<unsigned long long>(read.duplicates));
    for (const PrimPair& p : d.missing) std::printf("    missed (%u, %u)\n", p.a, p.b);
    for (const PrimPair& p : d.unexpected) std::printf("    extra (%u, %u)\n", p.a, p.b);
    for (const PrimPair& p : read.first_duplicates) std::printf("    duplicate (%u, %u)\n", p.a, p.b);
  }

  // The summary line; true when every frame matched.
  bool summarize() const {
    const size_t frames = files_.size();
    if (mismatched_ == 0 && unreadable_ == 0) {
      std::printf("  %-12s exact (%zu frames) in %s\n", "pairs", frames, dir_.string().c_str());
      return true;
    }
    std::printf("  %-12s MISMATCH in %llu of %zu frames, %llu unreadable, in %s: %llu missed, %llu extra, "
                "%llu duplicates\n",
                "pairs", static_cast<unsigned long long>(mismatched_), frames,
                static_cast<unsigned long long>(unreadable_), dir_.string().c_str(),
                static_cast<unsigned long long>(missed_), static_cast<unsigned long long>(extra_),
                static_cast<unsigned long long>(duplicates_));
    return false;
  }

 private:
  std::filesystem::path dir_;
  std::vector<std::filesystem::path> files_;
  uint32_t first_frame_;
  uint64_t mismatched_ = 0, unreadable_ = 0, missed_ = 0, extra_ = 0, duplicates_ = 0;
};

// The pipelines to check, each once, and the line each is shown under: names that build one
// pipeline (an alias, static = b and restructure = c, or a name given twice) share its run,
// shown under every distinct name given, "b = static". An unknown name is kept as it is,
// for make_pipelines to refuse.
struct VerifiedPipelines {
  std::vector<std::string> names, labels;
};

VerifiedPipelines distinct_pipelines(const std::vector<std::string>& given) {
  VerifiedPipelines out;
  std::vector<const PipelineKind*> kinds;
  for (const std::string& name : given) {
    const PipelineKind* kind = find_pipeline_kind(name);
    const auto same = [&](size_t k) {
      return out.names[k] == name || (kind && kinds[k] && kinds[k]->builds == kind->builds);
    };
    size_t k = 0;
    while (k < kinds.size() && !same(k)) ++k;
    if (k < kinds.size()) {
      const bool named = out.names[k] == name || out.labels[k].find(" = " + name) != std::string::npos;
      if (!named) out.labels[k] += " = " + name;
      continue;
    }
    kinds.push_back(kind);
    out.names.push_back(name);
    out.labels.push_back(name);
  }
  return out;
}

}  // namespace

CLI::App* add_verify_command(CLI::App& app, CommonOptions& o, VerifyOptions& v) {
  auto* verify = app.add_subcommand("verify", "compare pipelines with the exact oracle, frame by frame");
  verify
      ->add_option("--pipelines,--pipeline", v.pipelines,
                   "pipelines to check, space- or comma-separated (default: all; none with --pairs or --write-pairs)")
      ->delimiter(',')
      ->group(kPipelineGroup);
  add_common(verify, o);
  add_restructure(verify, o);
  verify->add_option("--brute-limit", v.brute_limit,
                     "largest triangle count for the O(N^2) oracle; above it, CPU sort-and-sweep")
      ->group(kAccuracyGroup)
      ->capture_default_str();
  verify
      ->add_option("--pairs", v.pairs_dir,
                   "check an outside method's pairs against the oracle: a directory of one file a frame, "
                   "frame_N.txt (0-based triangle indices 'i j' a line) or frame_N.bin (uint32 pairs); "
                   "docs/extending.md")
      ->check(non_empty_path())
      ->group(kAccuracyGroup);
  add_measurement(verify, o);
  verify->add_option("--write-pairs", v.write_pairs_dir, "write the oracle's pairs of each frame into this directory, as --pairs reads them")
      ->check(non_empty_path())
      ->group(kOutputGroup);
  verify->add_option("--pairs-format", v.pairs_format, "format of the files --write-pairs writes")
      ->check(CLI::IsMember({"txt", "bin"}))
      ->group(kOutputGroup)
      ->capture_default_str();
  add_tuning(verify, o);
  return verify;
}

int verify_command(const CommonOptions& o, const VerifyOptions& v) {
  std::vector<std::string> pipelines = v.pipelines;
  const size_t brute_limit = v.brute_limit;
  const std::string device = resolve_device(o.device);
  const bool pairs_only = !v.pairs_dir.empty() || !v.write_pairs_dir.empty();
  if (!o.front_plan.empty())
    fail_usage("--front-cycle " + o.front_plan +
               ": a recorded plan replays on one pipeline; check it with run --pipeline P --front-cycle FILE "
               "--check every");
  if (!v.pairs_dir.empty() && !std::filesystem::is_directory(v.pairs_dir))
    fail_usage("--pairs " + v.pairs_dir + ": not a directory");
  // Every pipeline once: a name that only aliases a later one (static = b, restructure = c)
  // would check the same pipeline twice.
  if (pipelines.empty() && !pairs_only) {
    const std::vector<PipelineKind>& kinds = pipeline_kinds();
    for (size_t k = 0; k < kinds.size(); ++k) {
      const bool alias = std::any_of(kinds.begin() + k + 1, kinds.end(),
                                     [&](const PipelineKind& later) { return later.builds == kinds[k].builds; });
      if (!alias && kinds[k].name != oracle_pipeline()) pipelines.push_back(kinds[k].name);
    }
  }
  const VerifiedPipelines verified = distinct_pipelines(pipelines);
  pipelines = verified.names;
  std::vector<std::unique_ptr<Pipeline>> runs = make_pipelines(o, pipelines, device);
  print_environment(device);
  for (const std::string& line : ignored_option_warnings(o.given, pipelines))
    std::printf("warning: %s\n", line.c_str());
  Scene scene = load_scene(o);
  const Topology& topo = scene.source->topology();
  const FrameRange range = parse_frame_range(o.frames, scene.source->num_frames());
  const bool brute_oracle = topo.faces.size() <= brute_limit;
  // The oracle sees the same fat, swept or quantized boxes only as the brute-force pipeline.
  const PipelineConfig& c = o.config;
  if (!brute_oracle && (c.boxes.margin > 0 || c.boxes.swept || c.boxes.precision == BoxPrecision::q16))
    fail_usage("verify --box-margin/--boxes swept/--box-precision q16 needs the brute-force oracle (raise --brute-limit)");
  std::printf("verify: scene %s (%zu triangles), frames %u:%u, device %s, oracle %s\n",
              scene.name.c_str(), topo.faces.size(), range.first, range.last, device.c_str(),
              brute_oracle ? "brute force (same device)" : "sort-and-sweep (cpu)");
  // The files are matched to the frames before any work, so a missing one stops it.
  std::optional<PairsCheck> pairs_check;
  if (!v.pairs_dir.empty())
    pairs_check.emplace(v.pairs_dir, pairs_files_for_frames(v.pairs_dir, range.first, range.last), range.first);
  const PairsFormat write_format = v.pairs_format == "bin" ? PairsFormat::binary : PairsFormat::text;
  if (!v.write_pairs_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(v.write_pairs_dir, ec);
    if (ec) fail("--write-pairs " + v.write_pairs_dir + ": cannot create directory: " + ec.message());
  }
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
  const bool fp64 = c.boxes.precision == BoxPrecision::fp64;
  const bool keeps_double_pairs = fp64 || c.boxes.margin == 0;
  std::vector<uint64_t> double_missed(pipelines.size(), 0), double_extra(pipelines.size(), 0);
  uint64_t double_pairs = 0;
  PositionRounding rounding(fp64);
  std::vector<vec3d> positions;
  std::vector<vec3f> vertices;
  for (uint32_t f = range.first; f < range.last; ++f) {
    scene.source->positions(f, positions);
    rounding.round(positions, vertices);
    try {
      check_margin_in_float_range(vertices, c.boxes.margin, widens_boxes(c.boxes));
    } catch (const UsageError& e) {
      throw UsageError("frame " + std::to_string(f) + ": " + e.what());
    }
    std::vector<PrimPair> expected;
    if (oracle) {
      oracle->run_frame(positions);
      expected = oracle->sorted_pairs();
    } else {
      expected = sweep_oracle_pairs(topo, vertices, c.skip_adjacent);
    }
    if (!v.write_pairs_dir.empty())
      write_pairs_file(std::filesystem::path(v.write_pairs_dir) / pairs_file_name(f, write_format), expected,
                       {"cdbench verify --write-pairs: the oracle's pairs of scene " + scene.name + ", frame " +
                            std::to_string(f) + " (" + std::to_string(topo.faces.size()) + " triangles)",
                        "one pair a line: two 0-based triangle indices, the smaller first, sorted"});
    if (pairs_check) pairs_check->check_frame(f, uint32_t(topo.faces.size()), expected);
    if (runs.empty()) continue;
    const std::vector<PrimPair> exact = sweep_oracle_pairs(topo, positions, c.skip_adjacent);
    double_pairs += exact.size();
    for (size_t p = 0; p < runs.size(); ++p) {
      runs[p]->run_frame(positions);
      const std::vector<PrimPair> reported = runs[p]->sorted_pairs();
      const PairSetDiff d = diff_pair_sets(expected, reported);
      if (!d.equal()) {
        ++mismatched_frames[p];
        print_mismatch(verified.labels[p], f, d);
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
                verified.labels[p].c_str(), mismatched_frames[p] ? "MISMATCH" : "exact", range.last - range.first,
                static_cast<unsigned long long>(double_missed[p]), static_cast<unsigned long long>(double_pairs),
                lost ? " (LOST)" : "", static_cast<unsigned long long>(double_extra[p]));
    ok = ok && mismatched_frames[p] == 0 && !lost;
  }
  if (pairs_check) ok = pairs_check->summarize() && ok;
  if (!v.write_pairs_dir.empty())
    std::printf("verify: wrote the oracle's pairs of %u frames to %s\n", range.last - range.first,
                v.write_pairs_dir.c_str());
  if (c.tree.refit_every > 1 && !runs.empty())
    std::printf("verify: --refit-every %u is not conservative: bvh and the front pipelines may miss pairs\n",
                c.tree.refit_every);
  const char* matched = runs.empty()      ? (pairs_check ? "the pairs match the oracle" : "done")
                        : pairs_check ? "all pipelines and the pairs match the oracle"
                                      : "all pipelines match the oracle";
  std::printf("verify: %s\n", ok ? matched : "FAILED");
  return ok ? kExitOk : kExitFailure;
}

}  // namespace cdb
