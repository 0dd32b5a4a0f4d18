#include "compare_command.h"
#include "number_checks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <vector>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "damaged_file_guard.h"
#include "exact_number.h"
#include "exit_codes.h"
#include "cdbench/pipeline/plan_record.h"
#include "harness/results/results_reader.h"
#include "run_statistics.h"

namespace cdb {
namespace {

// Options that change the pair set (what counts as a pair: --skip-adjacent; the boxes:
// --box-*, --boxes, --refit-every) or how time is measured (--check's work between frames,
// --cold, --phase-timing, --warmup-ms). The frame range and warm-up are compared as the file
// resolved them; declared queries belong to the scene (its label and content hash).
constexpr const char* kIdentityOptions[] = {"skip-adjacent",    "box-precision", "box-margin",   "boxes",
                                            "refit-every",      "check",         "contact-distance",
                                            "contact-substeps", "cold",          "phase-timing", "warmup-ms"};

// Options that neither tell runs apart nor are the subject of a comparison: where the
// output went, how it was printed, how many passes were averaged (repeats combine), and
// what the identity already holds in resolved form.
bool ignored_option(const std::string& name) {
  for (const char* n : {"out", "label", "json", "quiet", "save-pairs", "repeat", "max-noise", "scenes-dir",
                        "device", "frames", "pipeline", "scene", "set", "warmup"})
    if (name == n) return true;
  return false;
}

std::string option_value(const nlohmann::json& options, const std::string& name) {
  if (!options.contains(name)) return "(not recorded)";
  const nlohmann::json& v = options[name];
  return v.is_string() ? v.get<std::string>() : v.dump();
}

struct RunFile {
  ResultsOverview info;
  ResultsFrames frames;
  std::vector<double> measured_ms, measured_noise;
  uint64_t passes = 1;  // --repeat passes behind every measured frame (the fewest)
  // Every pass's measured frame times, [pass][frame] (/passes; empty for files before
  // schema 5), and every pass's plan (/plans; empty for pipelines without one).
  std::vector<std::vector<double>> pass_ms;
  ResultsPlans plans;
};

// One configuration of one side: its files are repeats of each other.
struct RunGroup {
  std::vector<std::pair<std::string, std::string>> identity;  // (field, value), in a fixed order
  std::string config;  // identity, content hash and every other recorded option
  std::string key;     // config and label: what makes files repeats of one run
  std::vector<RunFile> files;
  const ResultsOverview& first() const { return files.front().info; }
};

std::vector<std::pair<std::string, std::string>> identity_of(const ResultsOverview& r) {
  std::vector<std::pair<std::string, std::string>> id = {
      {"scene", r.scene_label},
      {"pipeline", r.pipeline},
      {"device", r.backend},
      {"device_name", r.device_name},
      {"frames", std::to_string(r.frame_first) + ":" + std::to_string(r.frame_last)},
      {"warmup", std::to_string(r.warmup)}};
  for (const char* o : kIdentityOptions) id.emplace_back(std::string("--") + o, option_value(r.options, o));
  return id;
}

std::string config_of(const ResultsOverview& r) {
  std::string key;
  for (const auto& [field, value] : identity_of(r)) key += field + "=" + value + "\n";
  key += "hash=" + r.input_hash + "\n";
  for (auto it = r.options.begin(); it != r.options.end(); ++it)
    if (!ignored_option(it.key())) key += "--" + it.key() + "=" + option_value(r.options, it.key()) + "\n";
  return key;
}

std::vector<std::string> expand(const std::string& arg) {
  namespace fs = std::filesystem;
  if (!fs::exists(arg)) fail_usage(arg + ": no such file or directory");
  if (!fs::is_directory(arg)) return {arg};
  std::vector<std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(arg))
    if (e.is_regular_file() && e.path().extension() == ".h5") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  return files;
}

// The side's complete runs, grouped by configuration. Incomplete files are left out with a
// note (their times cover other frames); unreadable ones fail the command.
std::vector<RunGroup> load_side(const std::string& arg, const char* side) {
  std::vector<RunGroup> groups;
  for (const std::string& path : expand(arg)) {
    RunFile f;
    const DamagedFileGuard guard("compare", path);
    f.info = read_results_overview(path);
    if (f.info.status != "complete") {
      std::fprintf(stderr, "cdbench: compare: %s: %s run, left out\n", path.c_str(), f.info.status.c_str());
      continue;
    }
    f.frames = read_results_frames(path);
    const size_t rows = f.frames.total_ms.size();
    if (rows == 0) continue;
    // The frames the summary measured: the same warm-up rule (at least one frame stays).
    const size_t skip = std::min<size_t>(f.info.warmup, rows - 1);
    f.measured_ms.assign(f.frames.total_ms.begin() + ptrdiff_t(skip), f.frames.total_ms.end());
    f.measured_noise.assign(f.frames.total_noise.begin() + ptrdiff_t(skip), f.frames.total_noise.end());
    f.passes = *std::min_element(f.frames.repeats.begin() + ptrdiff_t(skip), f.frames.repeats.end());
    const ResultsPasses passes = read_results_passes(path);
    f.pass_ms.assign(passes.passes, {});
    for (size_t row = skip; row < passes.total_ms.size(); ++row)
      for (size_t p = 0; p < passes.passes; ++p) f.pass_ms[p].push_back(passes.total_ms[row][p]);
    f.plans = read_results_plans(path);
    const std::string config = config_of(f.info), key = config + "label=" + f.info.label;
    auto g = std::find_if(groups.begin(), groups.end(), [&](const RunGroup& x) { return x.key == key; });
    if (g == groups.end()) {
      groups.push_back({identity_of(f.info), config, key, {}});
      g = groups.end() - 1;
    }
    g->files.push_back(std::move(f));
  }
  if (groups.empty()) fail(std::string(side) + " " + arg + ": no complete results files");
  return groups;
}

// What compare tests: one metric value per measured pass, pooled over the side's files,
// where every file keeps its passes (/passes); else one per file where there are several;
// else the one run's value (too few to test). `over` says which, `note` what is missing.
struct Samples {
  std::vector<double> values;
  CiBasis over = CiBasis::passes;
  std::string note;
};

Samples samples_of(const RunGroup& g, Metric m) {
  Samples s;
  const bool kept = std::all_of(g.files.begin(), g.files.end(), [](const RunFile& f) { return !f.pass_ms.empty(); });
  if (kept) {
    s.over = g.files.size() > 1 ? CiBasis::repeats : CiBasis::passes;
    for (const RunFile& f : g.files)
      for (const auto& pass : f.pass_ms) s.values.push_back(metric_of(pass, m));
    return s;
  }
  s.over = g.files.size() > 1 ? CiBasis::repeats : CiBasis::frames;
  for (const RunFile& f : g.files) s.values.push_back(metric_of(f.measured_ms, m));
  const auto means_only = [](const RunFile& f) { return f.pass_ms.empty() && f.passes > 1; };
  if (std::any_of(g.files.begin(), g.files.end(), means_only))
    s.note = "passes not kept (a file before schema 5 holds only their means)";
  return s;
}

Estimate estimate(const RunGroup& g, const Samples& s, Metric m) {
  if (s.values.size() > 1) {
    Estimate e = estimate_over_runs(s.values);
    e.basis = s.over;
    return e;
  }
  const RunFile& f = g.files.front();
  if (f.passes > 1) return estimate_over_passes(f.measured_ms, f.measured_noise, f.passes, m);
  return estimate_over_frames(f.measured_ms, m);
}

// Identity fields that differ, as "field: A value vs B value"; the content hash only where
// both files recorded one.
std::vector<std::string> differences(const RunGroup& a, const RunGroup& b) {
  std::vector<std::string> d;
  for (size_t i = 0; i < a.identity.size(); ++i)
    if (a.identity[i].second != b.identity[i].second)
      d.push_back(a.identity[i].first + ": '" + a.identity[i].second + "' in A, '" + b.identity[i].second + "' in B");
  const std::string &ha = a.first().input_hash, &hb = b.first().input_hash;
  if (!ha.empty() && !hb.empty() && ha != hb)
    d.push_back("input_hash: " + ha + " in A, " + hb + " in B (same scene name, other frames)");
  return d;
}

struct Row {
  const RunGroup* a;
  const RunGroup* b;
  std::vector<std::string> mismatch;  // with --allow-mismatch: what differs
  Estimate ea, eb;
  double change = 0;
  Verdict v = Verdict::unchanged;
  Decision decision;
  std::vector<uint32_t> plan_differ;  // frames where the passes of A and B ran different plans
  size_t pair_frames = 0, pair_differ = 0;  // frames of both, and those with other pair counts
  std::string hash;                         // same | differs | unknown
};

// Pair counts of the frames both runs have (their first files: the repeats of a run
// report the same pairs, --repeat checks it).
void compare_pairs(Row& row) {
  const ResultsFrames &fa = row.a->files.front().frames, &fb = row.b->files.front().frames;
  std::map<uint64_t, uint64_t> pairs_a;
  for (size_t i = 0; i < fa.frame.size(); ++i) pairs_a[fa.frame[i]] = fa.pairs[i];
  for (size_t i = 0; i < fb.frame.size(); ++i) {
    const auto it = pairs_a.find(fb.frame[i]);
    if (it == pairs_a.end()) continue;
    ++row.pair_frames;
    row.pair_differ += it->second != fb.pairs[i];
  }
}

// The frames where the passes of both sides (every file's every pass) did not all run the
// same plan step: their times are of other work, whatever the verdict. None where neither
// side records plans.
void compare_plans(Row& row) {
  std::map<uint32_t, std::set<std::string>> steps;
  for (const RunGroup* g : {row.a, row.b})
    for (const RunFile& f : g->files)
      for (const RecordedPlan& pass : f.plans.passes)
        for (const PlannedFrame& frame : pass.frames) steps[frame.frame].insert(format_plan_step(frame.step));
  for (const auto& [frame, distinct] : steps)
    if (distinct.size() > 1) row.plan_differ.push_back(frame);
}

std::vector<Row> match(const std::vector<RunGroup>& as, const std::vector<RunGroup>& bs, bool allow_mismatch) {
  std::vector<Row> rows;
  std::set<const RunGroup*> used;
  for (const RunGroup& a : as) {
    std::vector<const RunGroup*> same;
    for (const RunGroup& b : bs)
      if (differences(a, b).empty()) same.push_back(&b);
    // Several B runs of this identity (other tuning knobs, other labels): the one of the
    // same configuration, if there is exactly one.
    if (same.size() > 1) {
      std::vector<const RunGroup*> exact;
      for (const RunGroup* b : same)
        if (b->config == a.config) exact.push_back(b);
      if (exact.size() != 1)
        fail_usage("A run " + a.files.front().info.path + " matches " + std::to_string(same.size()) +
                   " runs of B (" + same[0]->files.front().info.path + ", " + same[1]->files.front().info.path +
                   ", ...): compare files or directories that hold one run per configuration");
      same = exact;
    }
    Row row{&a, nullptr, {}, {}, {}, 0, Verdict::unchanged, {}, {}, 0, 0, ""};
    if (same.size() == 1) {
      row.b = same.front();
    } else {
      // No B run of this identity: the nearest one says which option differs.
      const RunGroup* nearest = nullptr;
      size_t fewest = SIZE_MAX;
      for (const RunGroup& b : bs) {
        const size_t n = differences(a, b).size();
        if (n < fewest) {
          fewest = n;
          nearest = &b;
        }
      }
      row.b = nearest;
      row.mismatch = differences(a, *nearest);
      if (!allow_mismatch) {
        std::string all;
        for (const auto& d : row.mismatch) all += "\n  " + d;
        fail_usage("runs do not match: A " + a.files.front().info.path + ", nearest B " +
                   nearest->files.front().info.path + ":" + all +
                   "\n(--allow-mismatch compares them anyway, flagged)");
      }
    }
    used.insert(row.b);
    rows.push_back(std::move(row));
  }
  for (const RunGroup& b : bs)
    if (!used.count(&b))
      std::fprintf(stderr, "cdbench: compare: B run %s matches no run of A, not compared\n",
                   b.files.front().info.path.c_str());
  return rows;
}

std::string fixed(double x, const char* format = "%.4f") {
  if (std::isnan(x)) return "";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char text[64];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

std::string files_of(const RunGroup& g) {
  std::string s;
  for (const RunFile& f : g.files) s += (s.empty() ? "" : " ") + f.info.path;
  return s;
}

std::string commits_of(const RunGroup& g) {
  std::set<std::string> shas;
  for (const RunFile& f : g.files) shas.insert(f.info.git_sha.empty() ? "unknown" : f.info.git_sha);
  std::string s;
  for (const auto& c : shas) s += (s.empty() ? "" : " ") + c;
  return s;
}

bool noisy(const RunGroup& g) {
  return std::any_of(g.files.begin(), g.files.end(), [](const RunFile& f) { return !f.info.noise_warning.empty(); });
}

std::string noisy_text(const Row& r) {
  const bool a = noisy(*r.a), b = noisy(*r.b);
  return a && b ? "A,B" : a ? "A" : b ? "B" : "";
}

// Why a side's runs were measured in poor conditions, as their files recorded it: a busy
// host or a noise warning (files before schema 5 record only the noise warning).
std::string poor_of(const RunGroup& g) {
  std::set<std::string> notes;
  for (const RunFile& f : g.files) {
    if (f.info.conditions == "poor") notes.insert(f.info.conditions_notes);
    else if (!f.info.noise_warning.empty()) notes.insert("noise warning");
  }
  std::string s;
  for (const auto& n : notes) s += (s.empty() ? "" : "; ") + n;
  return s;
}

std::string poor_text(const Row& r) {
  const std::string a = poor_of(*r.a), b = poor_of(*r.b);
  if (a.empty() && b.empty()) return "";
  if (b.empty()) return "A: " + a;
  if (a.empty()) return "B: " + b;
  return "A: " + a + " | B: " + b;
}

std::string join(const std::vector<std::string>& v, const char* sep) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
  return s;
}

// The columns of --csv and the keys of --json, the same whatever the inputs.
const std::vector<std::string>& columns() {
  static const std::vector<std::string> c = {
      "scene",      "pipeline",  "device",    "label_a",    "label_b",   "metric",       "a_ms",
      "a_ci_lo",    "a_ci_hi",   "a_n",       "a_ci_over",  "b_ms",      "b_ci_lo",      "b_ci_hi",
      "b_n",        "b_ci_over", "change_pct", "verdict",   "p_value",    "why",         "plan_differ",
      "pair_frames", "pair_differ", "input_hash",
      "mismatch",   "noisy",     "poor_conditions", "commit_a",  "commit_b",   "files_a",   "files_b"};
  return c;
}

// How a row's numbers that are not finite are written: JSON has no infinity (null), CSV
// says `inf`/`-inf` (an unbounded interval end); a NaN is no value in both.
enum class NonFinite { null, text };

nlohmann::json row_json(const Row& r, Metric m, NonFinite non_finite = NonFinite::null) {
  const ResultsOverview &a = r.a->first(), &b = r.b->first();
  const auto json_number = [non_finite](double x) {
    if (std::isfinite(x)) return nlohmann::json(x);
    return non_finite == NonFinite::text && std::isinf(x) ? nlohmann::json(exact_number(x)) : nlohmann::json(nullptr);
  };
  return {{"scene", a.scene_label},
          {"pipeline", a.pipeline},
          {"device", a.backend},
          {"label_a", a.label},
          {"label_b", b.label},
          {"metric", metric_name(m)},
          {"a_ms", json_number(r.ea.value)},
          {"a_ci_lo", json_number(r.ea.lo)},
          {"a_ci_hi", json_number(r.ea.hi)},
          {"a_n", r.ea.n},
          {"a_ci_over", ci_basis_name(r.ea.basis)},
          {"b_ms", json_number(r.eb.value)},
          {"b_ci_lo", json_number(r.eb.lo)},
          {"b_ci_hi", json_number(r.eb.hi)},
          {"b_n", r.eb.n},
          {"b_ci_over", ci_basis_name(r.eb.basis)},
          {"change_pct", json_number(r.change)},
          {"verdict", verdict_name(r.v)},
          {"p_value", json_number(r.decision.p)},
          {"why", r.decision.why},
          {"plan_differ", r.plan_differ.empty() ? std::string() : frame_list_text(r.plan_differ)},
          {"pair_frames", r.pair_frames},
          {"pair_differ", r.pair_differ},
          {"input_hash", r.hash},
          {"mismatch", join(r.mismatch, "; ")},
          {"noisy", noisy_text(r)},
          {"poor_conditions", poor_text(r)},
          {"commit_a", commits_of(*r.a)},
          {"commit_b", commits_of(*r.b)},
          {"files_a", files_of(*r.a)},
          {"files_b", files_of(*r.b)}};
}

// A CSV cell: numbers at full precision, as report --csv writes them.
std::string cell_text(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) return exact_number(v.get<double>());
  return v.dump();
}

std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

std::string md_cell(const std::string& s) {
  std::string out;
  for (char c : s) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string interval(const Estimate& e) { return "[" + fixed(e.lo) + ", " + fixed(e.hi) + "]"; }

void print_markdown(const std::vector<Row>& rows, const CompareOptions& c, Metric m) {
  std::printf("%s per-frame ms (warm-up left out), B against A; threshold %.1f%%\n\n", metric_name(m),
              c.threshold_pct);
  std::printf("| scene | pipeline | device | A | A 95%% CI | B | B 95%% CI | change | verdict | pairs | flags |\n");
  std::printf("| --- | --- | --- | ---: | --- | ---: | --- | ---: | --- | --- | --- |\n");
  for (const Row& r : rows) {
    const ResultsOverview& a = r.a->first();
    std::vector<std::string> flags;
    if (!r.mismatch.empty()) flags.push_back("**MISMATCH: " + join(r.mismatch, "; ") + "**");
    if (!poor_text(r).empty()) flags.push_back("poor conditions (" + poor_text(r) + ")");
    else if (!noisy_text(r).empty()) flags.push_back("noisy run (" + noisy_text(r) + ")");
    if (r.hash == "unknown") flags.push_back("input hash not recorded");
    if (!r.plan_differ.empty())
      flags.push_back("**PLANS DIFFER at frames " + frame_list_text(r.plan_differ) + "**");
    if (!r.decision.why.empty() && r.decision.why.rfind("poor conditions", 0) != 0)
      flags.push_back(r.decision.why);
    const std::string pairs = r.pair_frames == 0 ? "no common frames"
                              : r.pair_differ   ? "**DIFFER in " + std::to_string(r.pair_differ) + " of " +
                                                    std::to_string(r.pair_frames) + " frames**"
                                                : "same (" + std::to_string(r.pair_frames) + " frames)";
    const auto side = [](const Estimate& e) {
      return std::string(ci_basis_name(e.basis)) + " n=" + std::to_string(e.n);
    };
    std::printf("| %s | %s | %s | %s | %s over %s | %s | %s over %s | %s%% | %s | %s | %s |\n",
                md_cell(a.scene_label).c_str(), md_cell(a.pipeline).c_str(), md_cell(a.backend).c_str(),
                fixed(r.ea.value).c_str(), interval(r.ea).c_str(), side(r.ea).c_str(), fixed(r.eb.value).c_str(),
                interval(r.eb).c_str(), side(r.eb).c_str(), fixed(r.change, "%+.1f").c_str(), verdict_name(r.v),
                pairs.c_str(), md_cell(join(flags, "; ")).c_str());
  }
  std::printf("\nVerdict: Mann-Whitney U over the passes' values (pooled over a side's files; one value per file "
              "where a file keeps no passes), a difference at p < %.2f whose Hodges-Lehmann shift (the change) "
              "exceeds the threshold; inconclusive where conditions were poor or the samples too few. CI: Student "
              "t over the same values (passes, repeats), else over one pass's frames.\n",
              kSignificance);
  for (const Row& r : rows) {
    const ResultsOverview &a = r.a->first(), &b = r.b->first();
    std::printf("\n- %s %s %s: A %s%s (commit %s), B %s%s (commit %s)", a.scene_label.c_str(), a.pipeline.c_str(),
                a.backend.c_str(), files_of(*r.a).c_str(), a.label.empty() ? "" : (" [" + a.label + "]").c_str(),
                commits_of(*r.a).c_str(), files_of(*r.b).c_str(),
                b.label.empty() ? "" : (" [" + b.label + "]").c_str(), commits_of(*r.b).c_str());
  }
  std::printf("\n");
}

}  // namespace

CLI::App* add_compare_command(CLI::App& app, CompareOptions& c) {
  auto* cmd = app.add_subcommand("compare", "compare the runs of results B against the matching runs of A");
  cmd->add_option("A", c.a, "results file, or a directory of them (sweep output too)")->required();
  cmd->add_option("B", c.b, "results file, or a directory of them")->required();
  cmd->add_option("--metric", c.metric, "per-frame statistic compared: mean, median or p95")
      ->check(CLI::IsMember({"mean", "median", "p95"}))
      ->capture_default_str();
  cmd->add_option("--threshold", c.threshold_pct,
                  "smallest change, in percent of A, that counts as a regression or an improvement")
      ->check(finite_at_least(0))
      ->capture_default_str();
  auto* csv = cmd->add_flag("--csv", c.csv, "CSV instead of Markdown (fixed columns)");
  cmd->add_flag("--json", c.json, "JSON instead of Markdown (fixed keys)")->excludes(csv);
  cmd->add_flag("--allow-mismatch", c.allow_mismatch,
                "compare runs whose scene, pipeline, device or pair-set or timing options differ, flagged");
  cmd->add_flag("--fail-on-regression", c.fail_on_regression, "exit 1 when a row regresses (for CI)");
  return cmd;
}

int compare_command(const CompareOptions& c) {
  const Metric m = parse_metric(c.metric);
  const std::vector<RunGroup> as = load_side(c.a, "A"), bs = load_side(c.b, "B");
  std::vector<Row> rows = match(as, bs, c.allow_mismatch);
  bool regressed = false;
  for (Row& r : rows) {
    const Samples sa = samples_of(*r.a, m), sb = samples_of(*r.b, m);
    r.ea = estimate(*r.a, sa, m);
    r.eb = estimate(*r.b, sb, m);
    r.decision = decide(sa.values, sb.values, c.threshold_pct, poor_text(r));
    const std::string note = !sa.note.empty() ? sa.note : sb.note;
    if (r.decision.verdict == Verdict::inconclusive && !note.empty() && r.decision.why.rfind("too few", 0) == 0)
      r.decision.why += " (" + note + ")";
    r.change = r.decision.shift_pct;
    r.v = r.decision.verdict;
    regressed |= r.v == Verdict::regression;
    compare_pairs(r);
    compare_plans(r);
    const std::string &ha = r.a->first().input_hash, &hb = r.b->first().input_hash;
    r.hash = ha.empty() || hb.empty() ? "unknown" : ha == hb ? "same" : "differs";
  }
  if (c.json) {
    nlohmann::json out = {{"metric", metric_name(m)}, {"threshold_pct", c.threshold_pct}, {"rows", nlohmann::json::array()}};
    for (const Row& r : rows) out["rows"].push_back(row_json(r, m));
    std::printf("%s\n", out.dump(2).c_str());
  } else if (c.csv) {
    std::vector<std::string> header;
    for (const auto& col : columns()) header.push_back(csv_cell(col));
    std::printf("%s\n", join(header, ",").c_str());
    for (const Row& r : rows) {
      const nlohmann::json j = row_json(r, m, NonFinite::text);
      std::vector<std::string> cells;
      for (const auto& col : columns()) cells.push_back(csv_cell(cell_text(j[col])));
      std::printf("%s\n", join(cells, ",").c_str());
    }
  } else {
    print_markdown(rows, c, m);
  }
  for (const Row& r : rows)
    if (!r.mismatch.empty())
      std::fprintf(stderr, "cdbench: compare: MISMATCHED runs compared (--allow-mismatch): %s\n",
                   join(r.mismatch, "; ").c_str());
  if (regressed && c.fail_on_regression) {
    std::fflush(stdout);
    std::fprintf(stderr,
                 "cdbench: compare: regression beyond %.1f%% and the noise (Mann-Whitney p < %.2f; "
                 "--fail-on-regression)\n",
                 c.threshold_pct, kSignificance);
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace cdb
