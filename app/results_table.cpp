#include "results_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "cell_status.h"
#include "damaged_file_guard.h"
#include "exit_codes.h"
#include "library_errors.h"

#include "core/error.h"
#include "core/phase.h"
#include "io/results_reader.h"

namespace cdb {
namespace {

struct Row {
  ResultsOverview r;
  std::string unreadable;  // why, when the file could not be read
  std::optional<CellStatus> process;  // how a sweep cell's process ended, when recorded
};

struct Inputs {
  std::vector<std::string> files;
  std::vector<std::pair<std::string, CellStatus>> missing;
  // Directory entries that could not be looked at (a link loop, a dangling link, no
  // permission), with why: said, and the rest reported.
  std::vector<std::pair<std::string, std::string>> skipped;
};

// A directory stands for every .h5 under it, and for every sweep cell recorded there
// (<cell>.status.json) without a results file (pending, running, or failed before writing
// one), so results copied together from many machines report as one table.
Inputs expand_inputs(const std::vector<std::string>& args) {
  namespace fs = std::filesystem;
  Inputs in;
  for (const auto& a : args) {
    std::error_code ec;
    // As compare does: a name that is not there is a mistyped argument, found before any
    // file is read; a file there that cannot be read is a row and exit 1.
    if (!fs::exists(fs::symlink_status(a, ec))) fail_usage(a + ": no such file or directory");
    if (!fs::is_directory(a, ec)) {
      in.files.push_back(a);
      continue;
    }
    std::vector<fs::path> found, statuses;
    fs::recursive_directory_iterator it(a, fs::directory_options::skip_permission_denied, ec);
    for (; !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const fs::path& p = it->path();
      std::error_code entry_ec;
      const bool regular = it->is_regular_file(entry_ec);
      if (entry_ec) {
        in.skipped.emplace_back(p.string(), path_error_text(entry_ec));
        continue;
      }
      if (!regular) {
        if (it->is_symlink(entry_ec) && !it->exists(entry_ec))
          in.skipped.emplace_back(p.string(), "a link to " + fs::read_symlink(p, entry_ec).string() + ", which does not exist");
        continue;
      }
      const std::string name = p.filename().string();
      if (p.extension() == ".h5") found.push_back(p);
      if (name.ends_with(".status.json")) statuses.push_back(p);
    }
    if (ec) in.skipped.emplace_back(a, "cannot list the directory: " + path_error_text(ec));
    std::sort(found.begin(), found.end());
    std::sort(statuses.begin(), statuses.end());
    for (const auto& f : found) in.files.push_back(f.string());
    for (const auto& st : statuses) {
      const std::optional<CellStatus> s = read_cell_status(st);
      const fs::path file = st.parent_path() / (s ? s->cell + ".h5" : "");
      if (s && !fs::exists(file, ec)) in.missing.emplace_back(file.string(), *s);
    }
  }
  return in;
}

std::string number(double x, const char* format = "%.3f") {
  if (std::isnan(x)) return "";
  char text[64];
  std::snprintf(text, sizeof text, format, x);
  return text;
}

// Phases in the pipeline's order; names this build does not know go last, by name.
size_t phase_rank(const std::string& name) {
  for (size_t p = 0; p < kPhaseCount; ++p)
    if (name == kPhaseNames[p]) return p;
  return kPhaseCount;
}

std::vector<std::string> phases_that_ran(const std::vector<Row>& rows) {
  std::vector<std::string> phases;
  for (const Row& row : rows)
    for (const auto& [phase, mean] : row.r.phase_means)
      if (std::find(phases.begin(), phases.end(), phase) == phases.end()) phases.push_back(phase);
  std::sort(phases.begin(), phases.end(), [](const std::string& a, const std::string& b) {
    const size_t ra = phase_rank(a), rb = phase_rank(b);
    return ra != rb ? ra < rb : a < b;
  });
  return phases;
}

// Options shown by their own columns already (scene and --set make the scene label, --label
// its column), different in every file by construction (--out), or about the console only
// (--json).
bool shown_elsewhere(const std::string& option) {
  for (const char* name : {"out", "scene", "set", "pipeline", "device", "label", "json"})
    if (option == name) return true;
  return false;
}

std::string option_text(const nlohmann::json& options, const std::string& name) {
  if (!options.contains(name)) return "";
  const nlohmann::json& v = options[name];
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "yes" : "no";
  if (v.is_array()) {
    std::string joined;
    for (const auto& e : v) joined += (joined.empty() ? "" : " ") + (e.is_string() ? e.get<std::string>() : e.dump());
    return joined;
  }
  return v.dump();
}

// The options whose values are not the same in every readable file, in name order: what
// sets the rows apart besides scene, pipeline and device.
std::vector<std::string> options_that_differ(const std::vector<Row>& rows) {
  std::vector<const nlohmann::json*> recorded;
  for (const Row& row : rows)
    if (row.unreadable.empty() && !row.r.options.empty()) recorded.push_back(&row.r.options);
  std::vector<std::string> names;
  for (const nlohmann::json* options : recorded)
    for (auto it = options->begin(); it != options->end(); ++it)
      if (!shown_elsewhere(it.key()) && std::find(names.begin(), names.end(), it.key()) == names.end())
        names.push_back(it.key());
  std::sort(names.begin(), names.end());
  std::vector<std::string> differ;
  for (const auto& name : names) {
    std::set<std::string> values;  // "absent" apart from any recorded value
    for (const nlohmann::json* options : recorded)
      values.insert(options->contains(name) ? "=" + option_text(*options, name) : "absent");
    if (values.size() > 1) differ.push_back(name);
  }
  return differ;
}

std::string status_text(const Row& row, bool csv) {
  // A pending cell's results file is a stale one from an earlier attempt, and a running
  // cell's is being written: the cell's own state says more.
  if (row.process && cell_in_progress(*row.process)) {
    const bool frames = row.process->state == "running" && row.unreadable.empty() && !row.r.status.empty() && !csv;
    return describe_progress(*row.process) +
           (frames ? ", " + std::to_string(row.r.frames_written) + "/" + std::to_string(row.r.frames_planned) + " frames"
                   : "");
  }
  if (row.process && row.unreadable.empty() && row.r.status.empty())
    return "failed, no results file: " + describe_exit(*row.process);
  // A process killed outright (out of memory, SIGKILL) leaves no error in its file, or a
  // file cut off before it could be read.
  const std::string killed = row.process && row.process->signal ? " (" + describe_exit(*row.process) + ")" : "";
  if (!row.unreadable.empty()) return "unreadable: " + row.unreadable + killed;
  if (row.r.status == "complete") return "complete";
  std::string s = row.r.status;
  if (!csv)
    s += " (" + std::to_string(row.r.frames_written) + "/" + std::to_string(row.r.frames_planned) + " frames)";
  if (!row.r.error.empty()) s += ": " + row.r.error;
  return s + killed;
}

std::string markdown_cell(std::string s) {
  std::string out;
  for (char c : s) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

int print_results_table(const std::vector<std::string>& args, bool csv) {
  const Inputs inputs = expand_inputs(args);
  std::vector<Row> rows;
  int rc = kExitOk;
  for (const auto& [entry, why] : inputs.skipped) {
    std::fprintf(stderr, "cdbench: report: skipped %s: %s\n", entry.c_str(), why.c_str());
    rc = kExitFailure;
  }
  if (inputs.files.empty() && inputs.missing.empty()) {
    std::string given;
    for (const auto& a : args) given += (given.empty() ? "" : ", ") + a;
    std::fprintf(stderr, "cdbench: report: no results files (.h5) or sweep cells under %s\n", given.c_str());
    return kExitFailure;
  }
  for (const auto& f : inputs.files) {
    Row row;
    const std::filesystem::path path(f);
    if (path.extension() == ".h5")
      row.process = read_cell_status(path.parent_path() / (path.stem().string() + ".status.json"));
    try {
      const DamagedFileGuard guard("report", f);
      row.r = read_results_overview(f);
    } catch (const std::exception& e) {
      row.r.path = f;
      row.unreadable = error_text(e);
      // A running cell's file is open for writing; its state is the row, not an error.
      if (!row.process || !cell_in_progress(*row.process)) {
        std::fprintf(stderr, "cdbench: report: %s\n", row.unreadable.c_str());
        rc = kExitFailure;
      }
    }
    if (row.process && cell_in_progress(*row.process)) {
      row.r.scene = row.process->scene;
      row.r.pipeline = row.process->pipeline;
      row.r.backend = row.process->device;
    }
    rows.push_back(std::move(row));
  }
  for (const auto& [file, s] : inputs.missing) {
    Row row;
    row.r.path = file;
    row.r.scene = s.scene;
    row.r.pipeline = s.pipeline;
    row.r.backend = s.device;
    row.process = s;
    rows.push_back(std::move(row));
  }
  // A failed sweep cell is a failure of what is reported, as an unreadable file is: the
  // exit code says so to a script that reads no table.
  const size_t failed = size_t(std::count_if(rows.begin(), rows.end(), [](const Row& row) {
    return row.process && row.process->state == "failed";
  }));
  if (failed) {
    std::fprintf(stderr, "cdbench: report: %zu sweep cell%s failed (see the status column)\n", failed,
                 failed == 1 ? "" : "s");
    rc = kExitFailure;
  }
  // CSV has the same columns for any set of files (every phase this build knows, the check
  // columns, the options as one JSON cell), so scripts can concatenate and index tables;
  // Markdown, for reading, shows only the phases that ran and the options that differ.
  std::vector<std::string> phases;
  if (csv)
    phases.assign(kPhaseNames.begin(), kPhaseNames.end());
  else
    phases = phases_that_ran(rows);
  const std::vector<std::string> options = csv ? std::vector<std::string>{} : options_that_differ(rows);
  const auto any = [&rows](auto has) {
    return std::any_of(rows.begin(), rows.end(), [&](const Row& row) { return row.unreadable.empty() && has(row.r); });
  };
  const bool checked = csv || any([](const ResultsOverview& r) { return r.checked_frames > 0; });
  const bool labels = csv || any([](const ResultsOverview& r) { return !r.label.empty(); });
  const bool hashes = csv || any([](const ResultsOverview& r) { return !r.input_hash.empty(); });
  const bool warnings = csv || any([](const ResultsOverview& r) { return !r.noise_warning.empty(); });

  std::vector<std::string> header = {"file", "scene", "pipeline", "device"};
  if (csv) header.insert(header.end(), {"label", "commit", "input_path", "input_hash"});
  header.push_back("triangles");
  for (const auto& o : options) header.push_back("--" + o);
  header.insert(header.end(), {"frames", "mean_ms", "noise_%", "median_ms", "p95_ms"});
  for (const auto& p : phases) header.push_back(p + "_ms");
  header.push_back("pairs");
  if (checked) header.insert(header.end(), {"recall_min", "precision_min", "contacts", "contact_precision"});
  header.insert(header.end(), {"syncs", csv ? "peak_bytes" : "peak_MiB"});
  if (csv) {
    header.insert(header.end(), {"noise_warning", "options_json"});
  } else {
    if (labels) header.push_back("label");
    header.push_back("commit");
    if (hashes) header.push_back("input");
    if (warnings) header.push_back("warning");
  }
  header.push_back("status");
  // Left-aligned in Markdown: the leading names and options, and label to status at the end.
  const size_t text_columns = 5 + options.size();
  const size_t trailing_text = size_t(labels) + 1 + size_t(hashes) + size_t(warnings) + 1;

  std::vector<std::vector<std::string>> table;
  for (const Row& row : rows) {
    const ResultsOverview& r = row.r;
    const bool read = row.unreadable.empty() && !r.status.empty();
    std::vector<std::string> cells = {r.path, r.scene_label.empty() ? r.scene : r.scene_label, r.pipeline,
                                      r.device_name.empty() ? r.backend : r.backend + ": " + r.device_name};
    if (csv) cells.insert(cells.end(), {r.label, r.git_sha, r.input_path, r.input_hash});
    cells.push_back(read ? std::to_string(r.triangles) : "");
    for (const auto& o : options) cells.push_back(read ? option_text(r.options, o) : "");
    cells.push_back(read ? std::to_string(r.frames_written) : "");
    const bool stats = row.unreadable.empty() && r.has_summary && r.measured_frames > 0;
    const double none = std::nan("");
    cells.push_back(number(stats ? r.mean_ms : none));
    // The noise beside the time it qualifies: with one pass there is none to report.
    cells.push_back(number(stats && r.repeats > 1 ? 100.0 * r.noise_median : none, "%.1f"));
    cells.push_back(number(stats ? r.median_ms : none));
    cells.push_back(number(stats ? r.p95_ms : none));
    for (const auto& p : phases) {
      double mean = none;
      for (const auto& [name, m] : r.phase_means)
        if (name == p) mean = m;
      cells.push_back(number(mean));
    }
    cells.push_back(number(stats ? r.pairs_mean : none, "%.0f"));
    if (checked) {
      const bool has_check = stats && r.checked_frames > 0;
      cells.push_back(number(has_check ? r.recall_min : none, "%.6f"));
      cells.push_back(number(has_check ? r.precision_min : none, "%.6f"));
      cells.push_back(has_check ? std::to_string(r.contacts) : "");
      cells.push_back(number(has_check ? r.contact_precision : none, "%.6f"));
    }
    cells.push_back(number(stats ? r.host_syncs_mean : none, "%.2f"));
    cells.push_back(!r.has_summary ? "" : csv ? std::to_string(r.peak_bytes) : number(double(r.peak_bytes) / (1 << 20), "%.2f"));
    if (csv) {
      nlohmann::json shown = nlohmann::json::object();
      for (auto it = r.options.begin(); it != r.options.end(); ++it)
        if (!shown_elsewhere(it.key())) shown[it.key()] = it.value();
      cells.insert(cells.end(), {r.noise_warning, read ? shown.dump() : ""});
    } else {
      if (labels) cells.push_back(r.label);
      // Twelve digits of the commit (and -dirty) are as many as `git log` needs.
      cells.push_back(r.git_sha);
      // The hash's first 8 digits tell inputs apart at a glance; CSV has all 16.
      if (hashes) cells.push_back(r.input_hash.substr(0, 8));
      if (warnings) cells.push_back(r.noise_warning.empty() ? "" : "noisy");
    }
    cells.push_back(status_text(row, csv));
    table.push_back(std::move(cells));
  }

  if (csv) {
    auto line = [](const std::vector<std::string>& cells) {
      std::string s;
      for (size_t i = 0; i < cells.size(); ++i) {
        if (i) s += ',';
        s += csv_cell(cells[i]);
      }
      std::printf("%s\n", s.c_str());
    };
    line(header);
    for (const auto& cells : table) line(cells);
    return rc;
  }
  auto line = [](const std::vector<std::string>& cells) {
    std::string s = "|";
    for (const auto& c : cells) {
      s += ' ';
      s += markdown_cell(c);
      s += " |";
    }
    std::printf("%s\n", s.c_str());
  };
  line(header);
  std::string rule = "|";
  for (size_t i = 0; i < header.size(); ++i)
    rule += (i < text_columns && i != 4) || i + trailing_text >= header.size() ? " --- |" : " ---: |";
  std::printf("%s\n", rule.c_str());
  for (const auto& cells : table) line(cells);
  return rc;
}

}  // namespace cdb
