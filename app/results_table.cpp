#include "results_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "cell_status.h"
#include "damaged_file_guard.h"
#include "exact_number.h"
#include "exit_codes.h"
#include "library_errors.h"
#include "plan_table.h"

#include "cdbench/core/error.h"
#include "cdbench/core/phase.h"
#include "harness/results/gpu_attributes.h"
#include "harness/results/results_reader.h"

namespace cdb {
namespace {

struct Row {
  ResultsOverview r;
  std::string unreadable;  // why, when the file could not be read
  std::optional<CellStatus> process;  // how a sweep cell's process ended, when recorded
};

// A column of the table: its header and how a row's cell reads; text columns are
// left-aligned in Markdown, numbers right-aligned.
using CellOf = std::function<std::string(const Row&)>;
struct Column {
  std::string name;
  bool text = true;
  CellOf cell;
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

// The GPU's conditions at a glance, where NVML read them: the SM clock and temperature
// before and after the measured passes ("" otherwise).
std::string gpu_cell(const ResultsOverview& r) {
  const auto source = r.gpu_text.find("gpu_source");
  if (source == r.gpu_text.end() || source->second != "nvml") return "";
  const auto value = [&r](const char* name) {
    const auto it = r.gpu_number.find(name);
    return it == r.gpu_number.end() ? std::nan("") : it->second;
  };
  char text[128];
  std::snprintf(text, sizeof text, "SM %.0f to %.0f MHz, %.0f to %.0f C", value("gpu_sm_clock_mhz_before"),
                value("gpu_sm_clock_mhz_after"), value("gpu_temperature_c_before"), value("gpu_temperature_c_after"));
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

// A Markdown table: text columns left-aligned, numbers right-aligned.
void print_markdown(const std::vector<std::string>& header, const std::vector<bool>& left,
                    const std::vector<std::vector<std::string>>& table) {
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
  for (const bool l : left) rule += l ? " --- |" : " ---: |";
  std::printf("%s\n", rule.c_str());
  for (const auto& cells : table) line(cells);
}

// The front plans of the files that record them, one row per pass, after the table; a
// file whose plans cannot be read is named on stderr and makes the exit code 1.
int print_plans(const std::vector<Row>& rows) {
  int rc = kExitOk;
  std::vector<std::vector<std::string>> table;
  for (const Row& row : rows) {
    if (!row.unreadable.empty() || !row.r.has_plans) continue;
    try {
      const DamagedFileGuard guard("report", row.r.path);
      for (auto& cells : plan_rows(row.r, read_results_plans(row.r.path))) table.push_back(std::move(cells));
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cdbench: report: %s\n", error_text(e).c_str());
      rc = kExitFailure;
    }
  }
  if (table.empty()) return rc;
  std::printf("\nPlans: the frames each pass built the trees, updated, generated (a maintenance, not a build) and "
              "restructured fronts\n\n");
  print_markdown(plan_table_header(), {true, true, false, true, true, true}, table);
  return rc;
}

// A CSV cell as a JSON value: a number column's text as the number it reads back as
// exactly (integers as integers), text as text; an empty cell, or a number that is not
// finite, is null.
nlohmann::ordered_json json_cell(const Column& column, const std::string& cell) {
  if (column.text) return cell;
  if (cell.empty()) return nullptr;
  if (cell.find_first_not_of("0123456789") == std::string::npos) return std::stoull(cell);
  const double x = std::strtod(cell.c_str(), nullptr);
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
}

}  // namespace

int print_results_table(const std::vector<std::string>& args, ReportFormat format) {
  // JSON has CSV's columns: every one whatever the files, and CSV's full-precision cells.
  const bool csv = format != ReportFormat::markdown;
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
  const bool by_query = csv || any([](const ResultsOverview& r) { return !std::isnan(r.pairs_self_mean); });
  const bool labels = csv || any([](const ResultsOverview& r) { return !r.label.empty(); });
  const bool hashes = csv || any([](const ResultsOverview& r) { return !r.input_hash.empty(); });
  const bool warnings =
      csv || any([](const ResultsOverview& r) { return !r.noise_warning.empty() || r.conditions == "poor"; });
  const bool plans = any([](const ResultsOverview& r) { return r.has_plans; });
  const bool gpus = any([](const ResultsOverview& r) { return !gpu_cell(r).empty(); });

  // One list of columns drives the header, the cells and the Markdown alignment.
  const double none = std::nan("");
  const auto read = [](const Row& row) { return row.unreadable.empty() && !row.r.status.empty(); };
  const auto stats = [](const Row& row) {
    return row.unreadable.empty() && row.r.has_summary && row.r.measured_frames > 0;
  };
  const auto has_check = [&stats](const Row& row) { return stats(row) && row.r.checked_frames > 0; };
  // Markdown rounds for reading; CSV keeps every digit.
  const auto shown = [csv](double x, const char* format = "%.3f") { return csv ? exact_number(x) : number(x, format); };
  std::vector<Column> columns;
  const auto text = [&columns](std::string name, CellOf cell) { columns.push_back({std::move(name), true, std::move(cell)}); };
  const auto numeric = [&columns](std::string name, CellOf cell) {
    columns.push_back({std::move(name), false, std::move(cell)});
  };
  text("file", [](const Row& row) { return row.r.path; });
  text("scene", [](const Row& row) { return row.r.scene_label.empty() ? row.r.scene : row.r.scene_label; });
  text("pipeline", [](const Row& row) { return row.r.pipeline; });
  text("device", [](const Row& row) {
    return row.r.device_name.empty() ? row.r.backend : row.r.backend + ": " + row.r.device_name;
  });
  if (csv) {
    text("label", [](const Row& row) { return row.r.label; });
    text("commit", [](const Row& row) { return row.r.git_sha; });
    text("input_path", [](const Row& row) { return row.r.input_path; });
    text("input_hash", [](const Row& row) { return row.r.input_hash; });
  }
  numeric("triangles", [&read](const Row& row) { return read(row) ? std::to_string(row.r.triangles) : ""; });
  for (const auto& o : options)
    text("--" + o, [&read, o](const Row& row) { return read(row) ? option_text(row.r.options, o) : ""; });
  // Frames run (rows written) and, below, frames measured (without the warm-up): two
  // counts, two names.
  numeric("frames_run", [&read](const Row& row) { return read(row) ? std::to_string(row.r.frames_written) : ""; });
  numeric("mean_ms", [&](const Row& row) { return shown(stats(row) ? row.r.mean_ms : none); });
  // The noise beside the time it qualifies: with one pass there is none to report.
  numeric("noise_pct", [&](const Row& row) {
    return shown(stats(row) && row.r.repeats > 1 ? 100.0 * row.r.noise_median : none, "%.1f");
  });
  numeric("median_ms", [&](const Row& row) { return shown(stats(row) ? row.r.median_ms : none); });
  numeric("p95_ms", [&](const Row& row) { return shown(stats(row) ? row.r.p95_ms : none); });
  if (csv) {
    numeric("frames_measured",
            [&stats](const Row& row) { return stats(row) ? std::to_string(row.r.measured_frames) : ""; });
    numeric("min_ms", [&](const Row& row) { return shown(stats(row) ? row.r.min_ms : none); });
    numeric("first_frame_ms", [&](const Row& row) { return shown(row.r.has_summary ? row.r.first_ms : none); });
  }
  for (const auto& p : phases)
    numeric(p + "_ms", [&none, &shown, p](const Row& row) {
      double mean = none;
      for (const auto& [name, m] : row.r.phase_means)
        if (name == p) mean = m;
      return shown(mean);
    });
  numeric("pairs", [&](const Row& row) { return shown(stats(row) ? row.r.pairs_mean : none, "%.0f"); });
  if (by_query) {
    numeric("pairs_self", [&](const Row& row) { return shown(stats(row) ? row.r.pairs_self_mean : none, "%.0f"); });
    numeric("pairs_inter", [&](const Row& row) { return shown(stats(row) ? row.r.pairs_inter_mean : none, "%.0f"); });
  }
  if (checked) {
    numeric("recall_min", [&](const Row& row) { return shown(has_check(row) ? row.r.recall_min : none, "%.6f"); });
    numeric("precision_min",
            [&](const Row& row) { return shown(has_check(row) ? row.r.precision_min : none, "%.6f"); });
    numeric("contacts", [&](const Row& row) { return has_check(row) ? std::to_string(row.r.contacts) : ""; });
    numeric("contact_precision",
            [&](const Row& row) { return shown(has_check(row) ? row.r.contact_precision : none, "%.6f"); });
  }
  // How the passes' front plans were made, beside the times they qualify.
  if (csv) {
    text("repeat_plan", [&read](const Row& row) { return read(row) ? row.r.repeat_plan : ""; });
    text("plan_source", [&read](const Row& row) { return read(row) ? row.r.plan_source : ""; });
    numeric("plan_mixed_frames",
            [&stats](const Row& row) { return stats(row) ? std::to_string(row.r.plan_mixed_frames) : ""; });
    numeric("warmup_frames",
            [&stats](const Row& row) { return stats(row) ? std::to_string(row.r.warmup_frames) : ""; });
  } else if (plans) {
    text("plan", [&read](const Row& row) { return read(row) ? plan_summary(row.r) : ""; });
  }
  // The passes behind the times, and whether the file keeps each one (/passes, schema 5) or
  // only their means.
  numeric(csv ? "passes_kept" : "passes", [&stats, csv](const Row& row) {
    if (!stats(row)) return std::string();
    if (csv) return std::to_string(row.r.passes_kept);
    const std::string n = std::isnan(row.r.repeats) ? "1" : std::to_string(uint64_t(row.r.repeats));
    return row.r.passes_kept || n == "1" ? n : n + " (means only)";
  });
  numeric("syncs", [&](const Row& row) { return shown(stats(row) ? row.r.host_syncs_mean : none, "%.2f"); });
  numeric(csv ? "peak_bytes" : "peak_MiB", [csv](const Row& row) {
    return !row.r.has_summary ? ""
           : csv              ? std::to_string(row.r.peak_bytes)
                              : number(double(row.r.peak_bytes) / (1 << 20), "%.2f");
  });
  if (csv) {
    text("noise_warning", [](const Row& row) { return row.r.noise_warning; });
    text("conditions", [](const Row& row) { return row.r.conditions; });
    text("conditions_notes", [](const Row& row) { return row.r.conditions_notes; });
    text("host_warning", [](const Row& row) { return row.r.host_warning; });
    numeric("host_busy_before", [](const Row& row) { return exact_number(row.r.host_busy_before); });
    numeric("host_busy_after", [](const Row& row) { return exact_number(row.r.host_busy_after); });
    for (const GpuAttribute& a : gpu_attributes()) {
      if (a.text)
        text(a.name, [name = a.name](const Row& row) {
          const auto it = row.r.gpu_text.find(name);
          return it == row.r.gpu_text.end() ? std::string() : it->second;
        });
      else
        numeric(a.name, [name = a.name](const Row& row) {
          const auto it = row.r.gpu_number.find(name);
          return it == row.r.gpu_number.end() ? std::string() : exact_number(it->second);
        });
    }
    text("options_json", [&read](const Row& row) {
      if (!read(row)) return std::string();
      nlohmann::json shown = nlohmann::json::object();
      for (auto it = row.r.options.begin(); it != row.r.options.end(); ++it)
        if (!shown_elsewhere(it.key())) shown[it.key()] = it.value();
      return shown.dump();
    });
  } else {
    if (labels) text("label", [](const Row& row) { return row.r.label; });
    // Twelve digits of the commit (and -dirty) are as many as `git log` needs.
    text("commit", [](const Row& row) { return row.r.git_sha; });
    // The hash's first 8 digits tell inputs apart at a glance; CSV has all 16.
    if (hashes) text("input", [](const Row& row) { return row.r.input_hash.substr(0, 8); });
    if (gpus) text("gpu", [](const Row& row) { return gpu_cell(row.r); });
    // A poor run says why in a word: its notes name a busy host, a noise warning, the GPU.
    if (warnings)
      text("warning", [](const Row& row) {
        if (row.r.conditions == "poor") return "poor conditions: " + row.r.conditions_notes;
        return row.r.noise_warning.empty() ? std::string() : std::string("noisy");
      });
  }
  text("status", [csv](const Row& row) { return status_text(row, csv); });

  std::vector<std::string> header;
  for (const Column& c : columns) header.push_back(c.name);
  std::vector<std::vector<std::string>> table;
  for (const Row& row : rows) {
    std::vector<std::string> cells;
    for (const Column& c : columns) cells.push_back(c.cell(row));
    table.push_back(std::move(cells));
  }

  if (format == ReportFormat::json) {
    // In the CSV's column order.
    nlohmann::ordered_json runs = nlohmann::ordered_json::array();
    for (const auto& cells : table) {
      nlohmann::ordered_json run = nlohmann::ordered_json::object();
      for (size_t i = 0; i < columns.size(); ++i) {
        // The options as the object they are, not as the text of a CSV cell.
        if (columns[i].name == "options_json")
          run["options"] = cells[i].empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json::parse(cells[i]);
        else
          run[columns[i].name] = json_cell(columns[i], cells[i]);
      }
      runs.push_back(std::move(run));
    }
    std::printf("%s\n", nlohmann::ordered_json{{"command", "report"}, {"runs", std::move(runs)}}.dump(2).c_str());
    return rc;
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
  std::vector<bool> aligned_left;
  for (const Column& c : columns) aligned_left.push_back(c.text);
  print_markdown(header, aligned_left, table);
  const int plans_rc = print_plans(rows);
  return rc != kExitOk ? rc : plans_rc;
}

}  // namespace cdb
