#include "sweep_plan.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <map>
#include <string_view>

#include "option_scope.h"
#include "cdbench/core/error.h"
#include "scenes/load/descriptor_object.h"

namespace cdb {
namespace {

using nlohmann::json;

// Characters kept in cell names; anything else becomes '-', so a name is a file name and a
// shell word everywhere.
std::string safe_name(const std::string& s) {
  std::string out;
  for (char c : s) {
    const bool keep = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '.' || c == '-' || c == '=' || c == '+';
    out += keep ? c : '-';
  }
  return out;
}

// A value as the command line gives it: strings as they are, numbers and booleans as JSON.
std::string value_text(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

// A scene that looks like a path is taken relative to the sweep file, so the file works
// from any directory; anything else is a scene name looked up in the scenes directory.
bool looks_like_path(const std::string& spec) {
  return spec.find('/') != std::string::npos || spec.ends_with(".json") || spec == "." || spec == "..";
}

std::vector<std::string> string_list(const json& j, const std::string& at, bool allow_single) {
  std::vector<std::string> out;
  if (allow_single && j.is_string()) return {j.get<std::string>()};
  if (!j.is_array() || j.empty()) fail(at + ": must be a non-empty list of strings");
  for (size_t i = 0; i < j.size(); ++i) {
    if (!j[i].is_string() || j[i].get<std::string>().empty())
      fail(at + "/" + std::to_string(i) + ": must be a non-empty string");
    out.push_back(j[i].get<std::string>());
  }
  return out;
}

struct SceneEntry {
  std::string spec, label, frames;
  std::vector<std::pair<std::string, std::string>> set;
};

SceneEntry scene_entry(const json& j, const std::string& at, const std::filesystem::path& base,
                       const std::string& default_frames) {
  SceneEntry e;
  e.frames = default_frames;
  if (j.is_string()) {
    e.spec = j.get<std::string>();
  } else if (j.is_object()) {
    for (auto it = j.begin(); it != j.end(); ++it) {
      const std::string key = it.key(), here = at + "/" + key;
      if (key == "scene") {
        if (!it->is_string() || it->get<std::string>().empty()) fail(here + ": must be a non-empty string");
        e.spec = it->get<std::string>();
      } else if (key == "label") {
        if (!it->is_string() || safe_name(it->get<std::string>()) != it->get<std::string>() ||
            it->get<std::string>().empty())
          fail(here + ": must be a non-empty string of letters, digits, '.', '-', '=', '+'");
        e.label = it->get<std::string>();
      } else if (key == "frames") {
        if (!it->is_string()) fail(here + ": must be a string such as \"0:10\"");
        e.frames = it->get<std::string>();
      } else if (key == "set") {
        if (!it->is_object()) fail(here + ": must be an object of generator parameters");
        for (auto p = it->begin(); p != it->end(); ++p) {
          if (p->is_object() || p->is_array() || p->is_null())
            fail(here + "/" + p.key() + ": must be a number, string or boolean");
          e.set.emplace_back(p.key(), value_text(*p));
        }
      } else {
        fail(here + ": unknown key (scene, label, set, frames)");
      }
    }
    if (e.spec.empty()) fail(at + ": needs \"scene\"");
  } else {
    fail(at + ": must be a scene name, a path, or an object with \"scene\"");
  }
  const bool path = looks_like_path(e.spec);
  if (e.label.empty()) {
    std::filesystem::path p = std::filesystem::path(e.spec).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    e.label = path ? p.stem().string() : e.spec;
    for (const auto& [key, value] : e.set) e.label += "." + key + "=" + value;
    e.label = safe_name(e.label);
  }
  if (path) {
    // Without a trailing '/', so a directory of frames is named after the directory.
    std::filesystem::path p = std::filesystem::absolute(base / e.spec).lexically_normal();
    if (p.filename().empty()) p = p.parent_path();
    e.spec = p.string();
  }
  return e;
}

struct Axis {
  std::string option;
  std::vector<json> values;
};

Axis option_axis(const std::string& key, const json& j, const std::string& at,
                 const std::vector<RunOptionInfo>& run_options) {
  const auto known = std::find_if(run_options.begin(), run_options.end(),
                                  [&](const RunOptionInfo& o) { return o.name == key; });
  // The sweep sets these itself, per cell (option_table.cpp): an axis over one would be
  // ambiguous.
  if (sweep_sets(key))
    fail(at + ": set by the sweep itself (use scenes, pipelines, devices, frames, warmup)");
  if (known == run_options.end()) fail(at + ": not an option of cdbench run");
  // --help makes run print its help and measure nothing.
  if (key == "help") fail(at + ": prints run's help instead of running a cell; not an option a sweep cell can take");
  Axis axis{key, {}};
  const json values = j.is_array() ? j : json::array({j});
  if (values.empty()) fail(at + ": empty list");
  for (size_t i = 0; i < values.size(); ++i) {
    const json& v = values[i];
    const std::string here = j.is_array() ? at + "/" + std::to_string(i) : at;
    if (known->flag && !v.is_boolean()) fail(here + ": --" + key + " is a flag: true or false");
    if (!known->flag && !(v.is_number() || v.is_string())) fail(here + ": must be a number or string");
    axis.values.push_back(v);
  }
  return axis;
}

}  // namespace

SweepPlan load_sweep(const std::filesystem::path& file, const std::vector<RunOptionInfo>& run_options,
                     const std::vector<std::string>& pipelines) {
  SweepPlan plan;
  plan.file = file.string();
  const std::string& at = plan.file;
  std::ifstream in(file);
  if (!in) fail(at + ": cannot open sweep file");
  const json j = parse_json_file(in, at);
  if (!j.is_object()) fail(at + ": must be a JSON object");
  for (auto it = j.begin(); it != j.end(); ++it) {
    static const std::vector<std::string> keys = {"description", "scenes", "pipelines", "devices",
                                                  "options", "frames", "warmup", "repeat"};
    if (std::find(keys.begin(), keys.end(), it.key()) == keys.end())
      fail(at + ": /" + it.key() + ": unknown key (description, scenes, pipelines, devices, options, frames, warmup, repeat)");
  }
  if (!j.contains("scenes")) fail(at + ": /scenes: missing");
  if (!j.contains("pipelines")) fail(at + ": /pipelines: missing");

  std::string frames;
  if (j.contains("frames")) {
    if (!j["frames"].is_string()) fail(at + ": /frames: must be a string such as \"0:10\"");
    frames = j["frames"].get<std::string>();
  }
  if (j.contains("warmup")) {
    if (!j["warmup"].is_number_unsigned()) fail(at + ": /warmup: must be a whole number >= 0");
    plan.warmup = j["warmup"].get<unsigned>();
  }
  // Read whole, so a repeat past 32 bits is counted as it is written, not wrapped.
  uint64_t repeat = 1;
  if (j.contains("repeat")) {
    if (!j["repeat"].is_number_unsigned() || j["repeat"].get<uint64_t>() == 0)
      fail(at + ": /repeat: must be a whole number >= 1");
    repeat = j["repeat"].get<uint64_t>();
  }

  const std::filesystem::path base = std::filesystem::absolute(file).parent_path();
  const json& scenes_json = j["scenes"];
  if (!scenes_json.is_array() || scenes_json.empty()) fail(at + ": /scenes: must be a non-empty list");
  std::vector<SceneEntry> scenes;
  for (size_t i = 0; i < scenes_json.size(); ++i)
    scenes.push_back(scene_entry(scenes_json[i], at + ": /scenes/" + std::to_string(i), base, frames));

  const std::vector<std::string> pipeline_list = string_list(j["pipelines"], at + ": /pipelines", false);
  for (size_t i = 0; i < pipeline_list.size(); ++i)
    if (std::find(pipelines.begin(), pipelines.end(), pipeline_list[i]) == pipelines.end())
      fail(at + ": /pipelines/" + std::to_string(i) + ": unknown pipeline '" + pipeline_list[i] + "'");

  // Devices are part of every cell name; "auto" is refused because it would name the same
  // cell differently on machines with and without a GPU.
  const std::vector<std::string> devices =
      j.contains("devices") ? string_list(j["devices"], at + ": /devices", false) : std::vector<std::string>{"cuda"};
  for (size_t i = 0; i < devices.size(); ++i)
    if (devices[i] != "cuda" && devices[i] != "cpu")
      fail(at + ": /devices/" + std::to_string(i) + ": must be cuda or cpu");

  std::vector<Axis> axes;
  if (j.contains("options")) {
    if (!j["options"].is_object()) fail(at + ": /options: must be an object of run options");
    for (auto it = j["options"].begin(); it != j["options"].end(); ++it)
      axes.push_back(option_axis(it.key(), *it, at + ": /options/" + it.key(), run_options));
  }

  // The cells counted from the axes before any is made: a product of a few long lists
  // reaches millions quickly, and making them would take minutes or all the memory before
  // a word is said.
  std::vector<std::pair<std::string, uint64_t>> factors = {
      {"scenes", scenes.size()}, {"pipelines", pipeline_list.size()}, {"devices", devices.size()}};
  for (const Axis& a : axes) factors.emplace_back("/options/" + a.option + " values", a.values.size());
  factors.emplace_back("repeats", repeat);
  uint64_t cells = 1;
  bool over = false;
  std::string product;
  for (const auto& [what, n] : factors) {
    // Every factor is at least 1; the product stops at the first that takes it past the
    // limit, so it cannot overflow.
    over = over || n > kMaxSweepCells / cells;
    if (!over) cells *= n;
    product += (product.empty() ? "" : " x ") + std::to_string(n) + " " + what;
  }
  if (over)
    fail(at + ": " + product + " make more than " + std::to_string(kMaxSweepCells) +
         " cells, the most a sweep may have; split it into several sweep files");

  // Cartesian product, scenes outermost and repeats innermost, so the cells of one scene
  // run together and a listing reads like a table. An axis whose option a pipeline ignores
  // (--front-cycle on bvh) is left out of that pipeline's cells, name and command line, so
  // its values make one cell there, run once, instead of identical runs under several names:
  // the odometer below does not step such an axis.
  for (size_t si = 0; si < scenes.size(); ++si) {
    const SceneEntry& s = scenes[si];
    for (const std::string& p : pipeline_list) {
      const PipelineKind* kind = find_pipeline_kind(p);
      std::vector<bool> applies(axes.size(), true);
      size_t ignored_values = 1;  // the cells of this pipeline each cell made stands for
      for (size_t a = 0; a < axes.size(); ++a) {
        applies[a] = !kind || scope_covers(option_scope("--" + axes[a].option), *kind);
        if (!applies[a]) ignored_values *= axes[a].values.size();
      }
      for (const std::string& d : devices) {
        std::vector<size_t> pick(axes.size(), 0);
        for (;;) {
          for (unsigned r = 1; r <= unsigned(repeat); ++r) {
            SweepCell c;
            c.scene = s.spec;
            c.scene_index = si;
            c.scene_label = s.label;
            c.set = s.set;
            c.frames = s.frames;
            c.pipeline = p;
            c.device = d;
            c.name = s.label + "_" + p + "_" + d;
            for (size_t a = 0; a < axes.size(); ++a) {
              if (!applies[a]) continue;
              const json& v = axes[a].values[pick[a]];
              c.options.emplace_back(axes[a].option, v);
              c.name += "_" + axes[a].option + "=" + safe_name(value_text(v));
            }
            if (repeat > 1) {
              c.repeat = r;
              c.name += "_r" + std::to_string(r);
            }
            plan.cells.push_back(std::move(c));
            plan.merged_cells += ignored_values - 1;
          }
          size_t a = 0;
          while (a < axes.size() && (!applies[a] || ++pick[a] == axes[a].values.size())) pick[a++] = 0;
          if (a == axes.size()) break;
        }
      }
      for (size_t a = 0; a < axes.size(); ++a)
        if (!applies[a] && axes[a].values.size() > 1) {
          std::vector<std::string>& ignoring = plan.ignored_axes["--" + axes[a].option];
          if (std::find(ignoring.begin(), ignoring.end(), p) == ignoring.end()) ignoring.push_back(p);
        }
    }
  }

  std::map<std::string, size_t> seen;
  for (size_t i = 0; i < plan.cells.size(); ++i) {
    const auto [it, added] = seen.emplace(plan.cells[i].name, i);
    if (!added)
      fail(at + ": cells " + std::to_string(it->second) + " and " + std::to_string(i) + " are both named '" +
           plan.cells[i].name + "'; give the scenes distinct \"label\"s");
  }
  return plan;
}

std::string merged_cells_line(const SweepPlan& plan) {
  if (plan.merged_cells == 0) return "";
  std::string why;
  for (const auto& [flag, pipelines] : plan.ignored_axes)
    why += (why.empty() ? "" : "; ") + not_applying_text({flag}, pipelines);
  return "sweep " + plan.file + ": " + std::to_string(plan.merged_cells) + (plan.merged_cells == 1 ? " cell merged into another because its pipeline ignores the option: "
                                 : " cells merged into others because their pipeline ignores the option: ") +
         why;
}

std::filesystem::path cell_results_file(const std::filesystem::path& out_dir, const SweepCell& cell) {
  return out_dir / (cell.name + ".h5");
}

std::vector<std::string> cell_run_args(const SweepPlan& plan, const SweepCell& cell,
                                       const std::filesystem::path& out_dir, const std::string& scenes_dir) {
  std::vector<std::string> args = {"run", "--scene", cell.scene};
  for (const auto& [key, value] : cell.set) args.insert(args.end(), {"--set", key + "=" + value});
  if (!scenes_dir.empty()) args.insert(args.end(), {"--scenes-dir", scenes_dir});
  args.insert(args.end(), {"--pipeline", cell.pipeline, "--device", cell.device});
  if (!cell.frames.empty()) args.insert(args.end(), {"--frames", cell.frames});
  args.insert(args.end(), {"--warmup", std::to_string(plan.warmup)});
  for (const auto& [option, value] : cell.options) {
    if (value.is_boolean()) {
      if (value.get<bool>()) args.push_back("--" + option);
    } else {
      args.insert(args.end(), {"--" + option, value_text(value)});
    }
  }
  args.insert(args.end(), {"--out", cell_results_file(std::filesystem::absolute(out_dir), cell).string(), "--quiet"});
  return args;
}

std::string shell_quote(const std::string& word) {
  const bool plain = !word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || std::string_view("/._-=+:,@%").find(c) != std::string_view::npos;
  });
  if (plain) return word;
  std::string out = "'";
  for (char c : word) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string shell_line(const std::vector<std::string>& words) {
  std::string line;
  for (const auto& w : words) {
    if (!line.empty()) line += ' ';
    line += shell_quote(w);
  }
  return line;
}

}  // namespace cdb
