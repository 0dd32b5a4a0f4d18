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
#include "join_words.h"
#include "option_table.h"
#include "run_statistics.h"

namespace cdb {
namespace {

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
  // Identity, content hash and every other recorded option: what makes files repeats of
  // one run. Not the --label, a display name only: files of other labels pool.
  std::string config;
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
  // The options of the pair set and the timing (option_table.cpp). The frame range and
  // warm-up are compared as the file resolved them; declared queries belong to the scene
  // (its label and content hash).
  for (const std::string& o : identity_options()) id.emplace_back("--" + o, option_value(r.options, o));
  return id;
}

std::string config_of(const ResultsOverview& r) {
  std::string key;
  for (const auto& [field, value] : identity_of(r)) key += field + "=" + value + "\n";
  key += "hash=" + r.input_hash + "\n";
  for (auto it = r.options.begin(); it != r.options.end(); ++it)
    if (!ignored_by_compare(it.key())) key += "--" + it.key() + "=" + option_value(r.options, it.key()) + "\n";
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
    const std::string config = config_of(f.info);
    auto g = std::find_if(groups.begin(), groups.end(), [&](const RunGroup& x) { return x.config == config; });
    if (g == groups.end()) {
      groups.push_back({identity_of(f.info), config, {}});
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

// One value per process (file), its frames' mean over its passes. Where the sides ran
// different plans, a process's passes replay the one plan it chose, so they share its
// effect: they are not independent samples of the build, its processes are.
Samples process_samples_of(const RunGroup& g, Metric m) {
  Samples s;
  s.over = CiBasis::repeats;
  for (const RunFile& f : g.files) s.values.push_back(metric_of(f.measured_ms, m));
  return s;
}

Samples samples_of(const RunGroup& g, Metric m) {
  Samples s;
  const bool kept = std::all_of(g.files.begin(), g.files.end(), [](const RunFile& f) { return !f.pass_ms.empty(); });
  if (kept) {
    s.over = g.files.size() > 1 ? CiBasis::repeats : CiBasis::passes;
    for (const RunFile& f : g.files)
      for (const auto& pass : f.pass_ms) s.values.push_back(metric_of(pass, m));
    return s;
  }
  s = process_samples_of(g, m);
  s.over = g.files.size() > 1 ? CiBasis::repeats : CiBasis::frames;
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
  // Other frames under one scene name is worth saying; under other names it follows.
  const bool same_scene = a.first().scene_label == b.first().scene_label;
  if (!ha.empty() && !hb.empty() && ha != hb)
    d.push_back("input_hash: " + ha + " in A, " + hb + " in B (" +
                (same_scene ? "same scene name, other frames" : "the scenes differ") + ")");
  return d;
}

// One row of the comparison: a run of A against its run of B, or a run of one side only
// (the other nullptr).
struct Row {
  const RunGroup* a = nullptr;
  const RunGroup* b = nullptr;
  std::string only;                   // a run of one side only: what sets it apart from the other's nearest
  std::vector<std::string> mismatch;  // with --allow-mismatch: what differs
  Estimate ea, eb;
  double change = 0;
  Verdict v = Verdict::unchanged;
  Decision decision;
  std::vector<uint32_t> plan_differ;  // frames where the passes of A and B ran different plans
  size_t pair_frames = 0, pair_differ = 0;  // frames of both, and those with other pair counts
};

Row row_of(const RunGroup* a, const RunGroup* b) {
  Row row;
  row.a = a;
  row.b = b;
  return row;
}

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

// The run of the other side that g pairs with: the one of the same identity; where there
// are several (other tuning knobs), the one of g's very configuration. nullptr when none;
// several of one configuration cannot be told apart, a usage error.
const RunGroup* partner(const RunGroup& g, const char* side, const std::vector<RunGroup>& others,
                        const char* other_side) {
  std::vector<const RunGroup*> same;
  for (const RunGroup& o : others)
    if (differences(g, o).empty()) same.push_back(&o);
  if (same.size() <= 1) return same.empty() ? nullptr : same.front();
  std::vector<const RunGroup*> exact;
  for (const RunGroup* o : same)
    if (o->config == g.config) exact.push_back(o);
  if (exact.size() != 1)
    fail_usage(std::string(side) + " run " + g.files.front().info.path + " matches " + std::to_string(same.size()) +
               " runs of " + other_side + " (" + same[0]->files.front().info.path + ", " +
               same[1]->files.front().info.path +
               ", ...): compare files or directories that hold one run per configuration");
  return exact.front();
}

// The run of `others` with the fewest identity fields unlike g's, among those not taken.
const RunGroup* nearest(const RunGroup& g, const std::vector<RunGroup>& others,
                        const std::set<const RunGroup*>& taken) {
  const RunGroup* best = nullptr;
  size_t fewest = SIZE_MAX;
  for (const RunGroup& o : others) {
    const size_t n = differences(g, o).size();
    if (!taken.count(&o) && n < fewest) {
      fewest = n;
      best = &o;
    }
  }
  return best;
}

// What sets a run of one side only apart from the nearest run of the other.
std::string only_note(const RunGroup& g, bool in_a, const std::vector<RunGroup>& others) {
  const RunGroup* other = nearest(g, others, {});
  const std::vector<std::string> d = in_a ? differences(g, *other) : differences(*other, g);
  const std::string name = std::string(in_a ? "B" : "A") + " " + other->files.front().info.path;
  if (d.empty()) return "nearest " + name + " pairs with another run of this identity (other tuning options)";
  return "nearest " + name + ": " + join_words(d, "; ");
}

// Pairs the runs of A and B symmetrically: two runs pair when each is the other's partner.
// With allow_mismatch, a run left over on A pairs with the nearest run left over on B,
// flagged. Every run still without a pair is a row of its side only ("only in A", "only
// in B"); they do not stop the comparison, but when no run pairs at all nothing was
// compared: a usage error naming what differs.
std::vector<Row> match(const std::vector<RunGroup>& as, const std::vector<RunGroup>& bs, bool allow_mismatch) {
  std::vector<const RunGroup*> partner_of_a, partner_of_b;
  for (const RunGroup& a : as) partner_of_a.push_back(partner(a, "A", bs, "B"));
  for (const RunGroup& b : bs) partner_of_b.push_back(partner(b, "B", as, "A"));
  std::vector<Row> rows;
  std::set<const RunGroup*> paired;
  for (size_t i = 0; i < as.size(); ++i) {
    const RunGroup* b = partner_of_a[i];
    if (b && partner_of_b[size_t(b - bs.data())] == &as[i]) {
      rows.push_back(row_of(&as[i], b));
      paired.insert(&as[i]);
      paired.insert(b);
    }
  }
  if (allow_mismatch)
    for (const RunGroup& a : as) {
      if (paired.count(&a)) continue;
      const RunGroup* b = nearest(a, bs, paired);
      if (!b) break;
      Row row = row_of(&a, b);
      row.mismatch = differences(a, *b);
      rows.push_back(std::move(row));
      paired.insert(&a);
      paired.insert(b);
    }
  if (rows.empty()) {
    const RunGroup& a = as.front();
    const RunGroup& b = *nearest(a, bs, {});
    fail_usage("runs do not match: A " + a.files.front().info.path + ", nearest B " + b.files.front().info.path +
               ":\n  " + join_words(differences(a, b), "\n  ") + "\n(--allow-mismatch compares them anyway, flagged)");
  }
  for (const RunGroup& a : as)
    if (!paired.count(&a)) {
      Row row = row_of(&a, nullptr);
      row.only = only_note(a, true, bs);
      rows.push_back(std::move(row));
    }
  for (const RunGroup& b : bs)
    if (!paired.count(&b)) {
      Row row = row_of(nullptr, &b);
      row.only = only_note(b, false, as);
      rows.push_back(std::move(row));
    }
  for (const Row& r : rows)
    if (!r.a || !r.b)
      std::fprintf(stderr, "cdbench: compare: %s run %s matches no run of %s, listed as only in %s (%s)\n",
                   r.a ? "A" : "B", (r.a ? r.a : r.b)->files.front().info.path.c_str(), r.a ? "B" : "A",
                   r.a ? "A" : "B", r.only.c_str());
  return rows;
}

std::string fixed(double x, const char* format = "%.4f") {
  if (std::isnan(x)) return "";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char text[64];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

nlohmann::json files_of(const RunGroup& g) {
  nlohmann::json paths = nlohmann::json::array();
  for (const RunFile& f : g.files) paths.push_back(f.info.path);
  return paths;
}

// The side's --label values, each once, in file order: the files of one run may be named
// apart (pooling ignores labels).
nlohmann::json labels_of(const RunGroup& g) {
  nlohmann::json labels = nlohmann::json::array();
  for (const RunFile& f : g.files)
    if (!f.info.label.empty() && std::find(labels.begin(), labels.end(), f.info.label) == labels.end())
      labels.push_back(f.info.label);
  return labels;
}

// The side's files for reading, each with its label: "a.h5 [before] b.h5".
std::string labelled_files_of(const RunGroup& g) {
  std::string s;
  for (const RunFile& f : g.files)
    s += (s.empty() ? "" : " ") + f.info.path + (f.info.label.empty() ? "" : " [" + f.info.label + "]");
  return s;
}

// The side's commits, each once, sorted; "unknown" for a file that recorded none.
std::vector<std::string> commits_of(const RunGroup& g) {
  const std::set<std::string> shas = [&g] {
    std::set<std::string> s;
    for (const RunFile& f : g.files) s.insert(f.info.git_sha.empty() ? "unknown" : f.info.git_sha);
    return s;
  }();
  return {shas.begin(), shas.end()};
}

bool noisy(const RunGroup& g) {
  return std::any_of(g.files.begin(), g.files.end(), [](const RunFile& f) { return !f.info.noise_warning.empty(); });
}

// f of a side's run; the empty value of its type for the side of a one-sided row.
template <class F>
auto of_side(const RunGroup* g, F f) -> decltype(f(*g)) {
  return g ? f(*g) : decltype(f(*g)){};
}

std::string noisy_text(const Row& r) {
  const bool a = of_side(r.a, noisy), b = of_side(r.b, noisy);
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
  const std::string a = of_side(r.a, poor_of), b = of_side(r.b, poor_of);
  if (a.empty() && b.empty()) return "";
  if (b.empty()) return "A: " + a;
  if (a.empty()) return "B: " + b;
  return "A: " + a + " | B: " + b;
}

// The columns of --csv and the keys of --json, the same whatever the inputs.
const std::vector<std::string>& columns() {
  static const std::vector<std::string> c = {
      "scene",      "pipeline",  "device",    "label_a",    "label_b",   "metric",       "a_ms",
      "a_ci_lo",    "a_ci_hi",   "a_n",       "a_ci_over",  "b_ms",      "b_ci_lo",      "b_ci_hi",
      "b_n",        "b_ci_over", "change_pct", "verdict",   "p_value",    "why",         "plan_differ",
      "pair_frames", "pair_differ", "input_hash_a", "input_hash_b",
      "mismatch",   "noisy",     "poor_conditions", "commit_a",  "commit_b",   "files_a",   "files_b"};
  return c;
}

// How a row's numbers that are not finite are written: JSON has no infinity (null), CSV
// says `inf`/`-inf` (an unbounded interval end); a NaN is no value in both.
enum class NonFinite { null, text };

// The row's verdict: the test's, or the one side a run is of.
std::string verdict_text(const Row& r) {
  if (!r.b) return "only in A";
  if (!r.a) return "only in B";
  return verdict_name(r.v);
}

nlohmann::json row_json(const Row& r, Metric m, NonFinite non_finite = NonFinite::null) {
  const ResultsOverview& run = (r.a ? r.a : r.b)->first();
  const auto hash = [](const RunGroup& g) { return g.first().input_hash; };
  // A side's lists (labels, commits, files) as arrays, empty for the side of a one-sided row.
  const auto list = [](const RunGroup* g, auto of) { return g ? nlohmann::json(of(*g)) : nlohmann::json::array(); };
  const auto json_number = [non_finite](double x) {
    if (std::isfinite(x)) return nlohmann::json(x);
    return non_finite == NonFinite::text && std::isinf(x) ? nlohmann::json(exact_number(x)) : nlohmann::json(nullptr);
  };
  const auto side_n = [](const RunGroup* g, const Estimate& e) { return g ? nlohmann::json(e.n) : nlohmann::json(); };
  const auto side_over = [](const RunGroup* g, const Estimate& e) {
    return g ? nlohmann::json(ci_basis_name(e.basis)) : nlohmann::json();
  };
  const auto pairs = [&r](size_t n) { return r.a && r.b ? nlohmann::json(n) : nlohmann::json(); };
  const double none = std::nan("");
  const auto side_number = [&](const RunGroup* g, double x) { return json_number(g ? x : none); };
  return {{"scene", run.scene_label},
          {"pipeline", run.pipeline},
          {"device", run.backend},
          {"label_a", list(r.a, labels_of)},
          {"label_b", list(r.b, labels_of)},
          {"metric", metric_name(m)},
          {"a_ms", side_number(r.a, r.ea.value)},
          {"a_ci_lo", side_number(r.a, r.ea.lo)},
          {"a_ci_hi", side_number(r.a, r.ea.hi)},
          {"a_n", side_n(r.a, r.ea)},
          {"a_ci_over", side_over(r.a, r.ea)},
          {"b_ms", side_number(r.b, r.eb.value)},
          {"b_ci_lo", side_number(r.b, r.eb.lo)},
          {"b_ci_hi", side_number(r.b, r.eb.hi)},
          {"b_n", side_n(r.b, r.eb)},
          {"b_ci_over", side_over(r.b, r.eb)},
          {"change_pct", json_number(r.change)},
          {"verdict", verdict_text(r)},
          {"p_value", json_number(r.decision.p)},
          {"why", r.a && r.b ? r.decision.why : r.only},
          {"plan_differ", r.plan_differ.empty() ? std::string() : frame_list_text(r.plan_differ)},
          {"pair_frames", pairs(r.pair_frames)},
          {"pair_differ", pairs(r.pair_differ)},
          {"input_hash_a", of_side(r.a, hash)},
          {"input_hash_b", of_side(r.b, hash)},
          {"mismatch", join_words(r.mismatch, "; ")},
          {"noisy", noisy_text(r)},
          {"poor_conditions", poor_text(r)},
          {"commit_a", list(r.a, commits_of)},
          {"commit_b", list(r.b, commits_of)},
          {"files_a", list(r.a, files_of)},
          {"files_b", list(r.b, files_of)}};
}

// A CSV cell: numbers at full precision, as report --csv writes them; a list joined by
// list_separator.
std::string cell_text(const nlohmann::json& v, const char* list_separator) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::string joined;
    for (const auto& e : v) joined += (joined.empty() ? "" : list_separator) + cell_text(e, list_separator);
    return joined;
  }
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

// A side's cells for reading: the value, and the interval with what it is over; dashes for
// the side a one-sided row has no run of.
std::pair<std::string, std::string> side_cells(const RunGroup* g, const Estimate& e) {
  if (!g) return {"—", "—"};
  return {fixed(e.value), interval(e) + " over " + ci_basis_name(e.basis) + " n=" + std::to_string(e.n)};
}

// A side's files and commits under the table; "none" for the side of a one-sided row.
std::string side_files(const RunGroup* g) {
  return g ? labelled_files_of(*g) + " (commit " + join_words(commits_of(*g), " ") + ")" : "none";
}

void print_markdown(const std::vector<Row>& rows, const CompareOptions& c, Metric m) {
  std::printf("%s per-frame ms (warm-up left out), B against A; threshold %.1f%%\n\n", metric_name(m),
              c.threshold_pct);
  std::printf("| scene | pipeline | device | A | A 95%% CI | B | B 95%% CI | change | verdict | pairs | flags |\n");
  std::printf("| --- | --- | --- | ---: | --- | ---: | --- | ---: | --- | --- | --- |\n");
  for (const Row& r : rows) {
    const ResultsOverview& run = (r.a ? r.a : r.b)->first();
    std::vector<std::string> flags;
    if (!r.only.empty()) flags.push_back(r.only);
    if (!r.mismatch.empty()) flags.push_back("**MISMATCH: " + join_words(r.mismatch, "; ") + "**");
    if (!poor_text(r).empty()) flags.push_back("poor conditions (" + poor_text(r) + ")");
    else if (!noisy_text(r).empty()) flags.push_back("noisy run (" + noisy_text(r) + ")");
    if (r.a && r.b && (r.a->first().input_hash.empty() || r.b->first().input_hash.empty()))
      flags.push_back("input hash not recorded");
    if (!r.plan_differ.empty())
      flags.push_back("**PLANS DIFFER at frames " + frame_list_text(r.plan_differ) + "**");
    if (!r.decision.why.empty() && r.decision.why.rfind("poor conditions", 0) != 0)
      flags.push_back(r.decision.why);
    const std::string pairs = !r.a || !r.b       ? "—"
                              : r.pair_frames == 0 ? "no common frames"
                              : r.pair_differ      ? "**DIFFER in " + std::to_string(r.pair_differ) + " of " +
                                                       std::to_string(r.pair_frames) + " frames**"
                                                   : "same (" + std::to_string(r.pair_frames) + " frames)";
    const auto [a_value, a_interval] = side_cells(r.a, r.ea);
    const auto [b_value, b_interval] = side_cells(r.b, r.eb);
    std::printf("| %s | %s | %s | %s | %s | %s | %s | %s%s | %s | %s | %s |\n", md_cell(run.scene_label).c_str(),
                md_cell(run.pipeline).c_str(), md_cell(run.backend).c_str(), a_value.c_str(), a_interval.c_str(),
                b_value.c_str(), b_interval.c_str(), fixed(r.change, "%+.1f").c_str(),
                std::isnan(r.change) ? "" : "%", verdict_text(r).c_str(), pairs.c_str(),
                md_cell(join_words(flags, "; ")).c_str());
  }
  std::printf("\nVerdict: Mann-Whitney U over the passes' values (pooled over a side's files; one value per file "
              "where a file keeps no passes, or where the sides' plans differ), a difference at p < %.2f whose Hodges-Lehmann shift (the change) "
              "exceeds the threshold; inconclusive where a time is not finite, conditions were poor or the samples "
              "too few. CI: Student "
              "t over the same values (passes, repeats), on the log scale, else over one pass's frames. A run of "
              "one side only is a row of its own (only in A, only in B), with no verdict.\n",
              kSignificance);
  for (const Row& r : rows) {
    const ResultsOverview& run = (r.a ? r.a : r.b)->first();
    std::printf("\n- %s %s %s: A %s, B %s", run.scene_label.c_str(), run.pipeline.c_str(), run.backend.c_str(),
                side_files(r.a).c_str(), side_files(r.b).c_str());
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
    if (!r.a || !r.b) {
      // A run of one side only: its estimate, nothing to test it against.
      const RunGroup& g = r.a ? *r.a : *r.b;
      (r.a ? r.ea : r.eb) = estimate(g, samples_of(g, m), m);
      r.change = r.decision.p = std::nan("");
      continue;
    }
    const Samples sa = samples_of(*r.a, m), sb = samples_of(*r.b, m);
    r.ea = estimate(*r.a, sa, m);
    r.eb = estimate(*r.b, sb, m);
    compare_plans(r);
    const bool plans_differ = !r.plan_differ.empty();
    const Samples pa = plans_differ ? process_samples_of(*r.a, m) : sa, pb = plans_differ ? process_samples_of(*r.b, m) : sb;
    r.decision = decide(pa.values, pb.values, c.threshold_pct, poor_text(r));
    const bool too_few = r.decision.verdict == Verdict::inconclusive && r.decision.why.rfind("too few", 0) == 0;
    const std::string note = !sa.note.empty() ? sa.note : sb.note;
    if (too_few && plans_differ)
      r.decision.why = "plans differ at frames " + frame_list_text(r.plan_differ) + ", and " +
                       std::to_string(pa.values.size()) + " and " + std::to_string(pb.values.size()) +
                       " processes are too few to test: a process's passes replay its one plan, so only "
                       "processes are samples; replay one plan on both sides (--front-cycle FILE, as "
                       "bench/interleave.sh does) or give each side 4 or more runs";
    else if (too_few && !note.empty())
      r.decision.why += " (" + note + ")";
    r.change = r.decision.shift_pct;
    r.v = r.decision.verdict;
    regressed |= r.v == Verdict::regression;
    compare_pairs(r);
  }
  if (c.json) {
    nlohmann::json out = {{"metric", metric_name(m)}, {"threshold_pct", c.threshold_pct}, {"rows", nlohmann::json::array()}};
    for (const Row& r : rows) out["rows"].push_back(row_json(r, m));
    std::printf("%s\n", out.dump(2).c_str());
  } else if (c.csv) {
    std::vector<std::string> header;
    for (const auto& col : columns()) header.push_back(csv_cell(col));
    std::printf("%s\n", join_words(header, ",").c_str());
    for (const Row& r : rows) {
      const nlohmann::json j = row_json(r, m, NonFinite::text);
      std::vector<std::string> cells;
      // Labels are free text, so they are joined as Markdown shows them; commits and files
      // by spaces.
      for (const auto& col : columns())
        cells.push_back(csv_cell(cell_text(j[col], col.rfind("label_", 0) == 0 ? ", " : " ")));
      std::printf("%s\n", join_words(cells, ",").c_str());
    }
  } else {
    print_markdown(rows, c, m);
  }
  for (const Row& r : rows)
    if (!r.mismatch.empty())
      std::fprintf(stderr, "cdbench: compare: MISMATCHED runs compared (--allow-mismatch): %s\n",
                   join_words(r.mismatch, "; ").c_str());
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
