#include "verify_command.h"

#include <cstdio>
#include <memory>

#include "bruteforce/sweep_oracle.h"
#include "core/error.h"
#include "frame_range.h"
#include "geometry/position_rounding.h"
#include "report.h"

namespace cdb {

CLI::App* add_verify_command(CLI::App& app, CommonOptions& o, VerifyOptions& v) {
  auto* verify = app.add_subcommand("verify", "compare pipelines with the exact oracle, frame by frame");
  verify->add_option("--pipelines", v.pipelines, "pipelines to check (default: all)")->group(kPipelineGroup);
  add_common(verify, o);
  add_restructure(verify, o);
  verify->add_option("--brute-limit", v.brute_limit,
                     "largest triangle count for the O(N^2) oracle; above it, CPU sort-and-sweep")
      ->group(kAccuracyGroup)
      ->capture_default_str();
  add_tuning(verify, o);
  return verify;
}

int verify_command(const CommonOptions& o, const VerifyOptions& v) {
  std::vector<std::string> pipelines = v.pipelines;
  const size_t brute_limit = v.brute_limit;
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
  const PipelineConfig& c = o.config;
  if (!brute_oracle && (c.box_margin > 0 || c.swept_boxes || c.box_precision == BoxPrecision::q16))
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
  const bool fp64 = c.box_precision == BoxPrecision::fp64;
  const bool keeps_double_pairs = fp64 || c.box_margin == 0;
  std::vector<uint64_t> double_missed(pipelines.size(), 0), double_extra(pipelines.size(), 0);
  uint64_t double_pairs = 0;
  PositionRounding rounding(fp64);
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
      expected = sweep_oracle_pairs(topo, vertices, c.skip_adjacent);
    }
    const std::vector<PrimPair> exact = sweep_oracle_pairs(topo, positions, c.skip_adjacent);
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
  if (c.refit_every > 1)
    std::printf("verify: --refit-every %u is not conservative: bvh and the front pipelines may miss pairs\n",
                c.refit_every);
  std::printf("verify: %s\n", ok ? "all pipelines match the oracle" : "FAILED");
  return ok ? 0 : 1;
}

}  // namespace cdb
