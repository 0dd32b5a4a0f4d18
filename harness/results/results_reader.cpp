#include "harness/results/results_reader.h"

#include <algorithm>
#include <cerrno>
#include <cmath>

#include "cdbench/core/error.h"
#include "cdbench/core/phase.h"
#include "harness/results/gpu_attributes.h"
#include "harness/results/hdf5_handle.h"
#include "harness/results/results_file.h"
#include "scenes/load/scene_label.h"

namespace cdb {
namespace {

// The length of a table's column.
hsize_t rows_of(hid_t dataset, const std::string& ds) {
  h5::Handle space = h5::own(H5Dget_space(dataset), H5Sclose, ds, "get dataspace");
  hsize_t rows = 0;
  h5::check(H5Sget_simple_extent_dims(space.get(), &rows, nullptr), ds, "get size");
  return rows;
}

// One column of a table (/frames, /plans) as `T`, converted by HDF5 from whatever numeric
// type the file stores.
template <class T>
std::vector<T> read_column(hid_t root, const std::string& where, const char* name, hid_t memory_type,
                           const std::string& group = "frames") {
  using h5::own;
  const std::string path = group + "/" + name, ds = where + ": /" + path;
  h5::Handle d = own(H5Dopen2(root, path.c_str(), H5P_DEFAULT), H5Dclose, ds, "open dataset");
  const hsize_t rows = rows_of(d.get(), ds);
  std::vector<T> v(rows);
  if (rows) h5::check(H5Dread(d.get(), memory_type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), ds, "read");
  return v;
}

// A text column (fixed-width strings, NUL-padded) of a table.
std::vector<std::string> read_text_column(hid_t root, const std::string& where, const char* name,
                                          const std::string& group) {
  using h5::own;
  const std::string path = group + "/" + name, ds = where + ": /" + path;
  h5::Handle d = own(H5Dopen2(root, path.c_str(), H5P_DEFAULT), H5Dclose, ds, "open dataset");
  h5::Handle type = own(H5Dget_type(d.get()), H5Tclose, ds, "get type");
  const size_t width = H5Tget_size(type.get());
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) != 0 || width == 0 ||
      width > 4 * kTextColumnBytes)
    fail(ds + ": not a column of fixed-width strings");
  h5::Handle memory = own(H5Tcopy(H5T_C_S1), H5Tclose, ds, "copy string type");
  h5::check(H5Tset_size(memory.get(), width), ds, "set string size");
  h5::check(H5Tset_strpad(memory.get(), H5T_STR_NULLPAD), ds, "set string padding");
  const hsize_t rows = rows_of(d.get(), ds);
  std::vector<char> cells(rows * width);
  if (rows) h5::check(H5Dread(d.get(), memory.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, cells.data()), ds, "read");
  std::vector<std::string> v;
  for (hsize_t i = 0; i < rows; ++i) {
    const char* cell = cells.data() + i * width;
    v.emplace_back(cell, std::find(cell, cell + width, '\0'));
  }
  return v;
}

// A results file opened for reading; `where` names it in messages.
h5::Handle open_results(const std::filesystem::path& path, const std::string& where) {
  h5::silence_library_errors();
  if (!std::filesystem::is_regular_file(path)) fail(where + ": no such file");
  try {
    return h5::own(H5Fopen(where.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose, where, "open results file");
  } catch (const h5::IoError& e) {
    // A writer (a run still going) holds HDF5's exclusive lock on the file; the system's
    // "resource temporarily unavailable" says nothing of that.
    if (e.error_number == EWOULDBLOCK || e.error_number == EAGAIN)
      fail(where + ": the file is in use by another process (HDF5's file lock is held: a run still writing it?); "
                   "read it once that process ends");
    throw;
  }
}

// A read of the file at `path`, with HDF5's own failures (a file cut short by a full disk or
// a copy, a damaged address) said as what they mean for the file and what to do.
template <class Read>
auto read_guarded(const std::filesystem::path& path, Read read) {
  try {
    return read();
  } catch (const h5::LibraryError& e) {
    fail(path.string() + ": the results file is truncated or damaged and cannot be read (HDF5: " + e.reason +
         "); write it again (run --out FILE --overwrite) or restore it from a copy");
  }
}

}  // namespace

ResultsOverview read_results_overview(const std::filesystem::path& path) {
  return read_guarded(path, [&] {
    ResultsOverview r;
    r.path = path.string();
    const std::string where = r.path;
    const h5::Handle file = open_results(path, where);
    const hid_t root = file.get();
    const std::string at = where + ": /";
    if (!h5::has_attr(root, "schema_version")) fail(where + ": not a cdbench results file (no schema_version)");
    r.schema_version = h5::read_int_attr(root, "schema_version", at);
    // A newer writer may have moved or redefined what this reader takes for granted.
    if (r.schema_version > kResultsSchemaVersion || r.schema_version < 1)
      fail(where + ": schema_version " + std::to_string(r.schema_version) + " is not one this cdbench reads (1 to " +
           std::to_string(kResultsSchemaVersion) + "); read it with the cdbench that wrote it, or a newer one");
    r.status = h5::read_string_attr(root, "status", at);
    if (h5::has_attr(root, "error")) r.error = h5::read_string_attr(root, "error", at);
    r.scene = h5::read_string_attr(root, "scene", at);
    r.pipeline = h5::read_string_attr(root, "pipeline", at);
    r.backend = h5::read_string_attr(root, "backend", at);
    r.device_name = h5::read_string_attr(root, "device_name", at);
    r.frames_planned = uint64_t(h5::read_int_attr(root, "frame_last", at) - h5::read_int_attr(root, "frame_first", at));
    r.triangles = uint64_t(h5::read_int_attr(root, "triangles", at));
    r.frame_first = uint64_t(h5::read_int_attr(root, "frame_first", at));
    r.frame_last = uint64_t(h5::read_int_attr(root, "frame_last", at));
    const auto optional_text = [&](const char* name) {
      return h5::has_attr(root, name) ? h5::read_string_attr(root, name, at) : std::string();
    };
    r.git_sha = optional_text("git_sha");
    r.label = optional_text("label");
    r.input_path = optional_text("input_path");
    r.input_hash = optional_text("input_hash");
    r.noise_warning = optional_text("noise_warning");
    r.repeat_plan = optional_text("repeat_plan");
    r.plan_source = optional_text("plan_source");
    r.conditions = optional_text("conditions");
    r.conditions_notes = optional_text("conditions_notes");
    r.host_warning = optional_text("host_warning");
    r.cpu_model = optional_text("cpu_model");
    const auto optional_share = [&](const char* name) {
      return h5::has_attr(root, name) ? h5::read_double_attr(root, name, at) : std::nan("");
    };
    r.host_busy_before = optional_share("host_busy_before");
    r.host_busy_after = optional_share("host_busy_after");
    for (const GpuAttribute& a : gpu_attributes()) {
      if (!h5::has_attr(root, a.name.c_str())) continue;
      if (a.text) r.gpu_text[a.name] = h5::read_string_attr(root, a.name.c_str(), at);
      else r.gpu_number[a.name] = h5::read_double_attr(root, a.name.c_str(), at);
    }
    if (h5::has_attr(root, "warmup")) r.warmup = uint64_t(h5::read_int_attr(root, "warmup", at));
    if (h5::has_attr(root, "cold")) r.cold = h5::read_int_attr(root, "cold", at) != 0;
    if (h5::has_attr(root, "params_json")) {
      const std::string text = h5::read_string_attr(root, "params_json", at);
      const nlohmann::json params = nlohmann::json::parse(text, nullptr, false);
      if (params.is_discarded() || !params.is_object()) fail(at + "params_json: not a JSON object");
      if (params.contains("options") && params["options"].is_object()) r.options = params["options"];
    }
    if (h5::has_attr(root, "scene_label")) {
      r.scene_label = h5::read_string_attr(root, "scene_label", at);
    } else {
      std::vector<std::string> sets;
      const nlohmann::json given = r.options.value("set", nlohmann::json::array());
      for (const auto& kv : given.is_array() ? given : nlohmann::json::array({given}))
        if (kv.is_string()) sets.push_back(kv.get<std::string>());
      r.scene_label = scene_label(r.scene, parse_set_overrides(sets));
    }

    const std::string ds = where + ": /frames/frame";
    const h5::Handle frames = h5::own(H5Dopen2(root, "frames/frame", H5P_DEFAULT), H5Dclose, ds, "open dataset");
    r.frames_written = rows_of(frames.get(), ds);

    r.has_plans = H5Lexists(root, "plans", H5P_DEFAULT) > 0;
    if (H5Lexists(root, "passes", H5P_DEFAULT) > 0) {
      const std::string pg = where + ": /passes";
      h5::Handle g = h5::own(H5Gopen2(root, "passes", H5P_DEFAULT), H5Gclose, pg, "open group");
      r.passes_kept = uint64_t(h5::read_int_attr(g.get(), "passes", pg));
    }
    if (H5Lexists(root, "summary", H5P_DEFAULT) <= 0) return r;
    const std::string st = where + ": /summary";
    h5::Handle summary = h5::own(H5Gopen2(root, "summary", H5P_DEFAULT), H5Gclose, st, "open group");
    const hid_t s = summary.get();
    r.has_summary = true;
    r.measured_frames = uint64_t(h5::read_int_attr(s, "measured_frames", st));
    r.mean_ms = h5::read_double_attr(s, "t_total_ms_mean", st);
    r.median_ms = h5::read_double_attr(s, "t_total_ms_median", st);
    r.p95_ms = h5::read_double_attr(s, "t_total_ms_p95", st);
    // Files written before the minimum was kept have none.
    r.min_ms = h5::has_attr(s, "t_total_ms_min") ? h5::read_double_attr(s, "t_total_ms_min", st) : std::nan("");
    r.first_ms = h5::read_double_attr(s, "first_frame_ms", st);
    r.pairs_mean = h5::read_double_attr(s, "pairs_mean", st);
    r.peak_bytes = uint64_t(h5::read_int_attr(s, "peak_bytes", st));
    const auto optional_double = [&](const char* name) {
      return h5::has_attr(s, name) ? h5::read_double_attr(s, name, st) : std::nan("");
    };
    r.repeats = h5::has_attr(s, "repeats") ? double(h5::read_int_attr(s, "repeats", st)) : std::nan("");
    r.noise_median = optional_double("noise_median");
    r.pairs_self_mean = optional_double("pairs_self_mean");
    r.pairs_inter_mean = optional_double("pairs_inter_mean");
    r.host_syncs_mean = optional_double("host_syncs_mean");
    if (h5::has_attr(s, "plan_mixed_frames"))
      r.plan_mixed_frames = uint64_t(h5::read_int_attr(s, "plan_mixed_frames", st));
    if (h5::has_attr(s, "warmup_frames")) r.warmup_frames = uint64_t(h5::read_int_attr(s, "warmup_frames", st));
    if (h5::has_attr(s, "checked_frames")) r.checked_frames = uint64_t(h5::read_int_attr(s, "checked_frames", st));
    if (r.checked_frames) {
      r.recall_min = h5::read_double_attr(s, "recall_min", st);
      r.precision_min = h5::read_double_attr(s, "precision_min", st);
      // Files written before the contact count have none.
      r.contacts = h5::has_attr(s, "contacts") ? uint64_t(h5::read_int_attr(s, "contacts", st)) : 0;
      r.contact_precision = optional_double("contact_precision");
    }
    // Phases are whatever t_<phase>_ms_mean attributes the file has, so files written before
    // or after a phase was added read the same way.
    const std::string prefix = "t_", suffix = "_ms_mean";
    for (const std::string& name : h5::attr_names(s, st)) {
      if (name.size() <= prefix.size() + suffix.size() || name.rfind(prefix, 0) != 0 ||
          name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      const std::string phase = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
      if (phase == "total") continue;
      const std::string frames_attr = prefix + phase + "_ms_frames";
      if (h5::has_attr(s, frames_attr.c_str()) && h5::read_int_attr(s, frames_attr.c_str(), st) == 0) continue;
      r.phase_means.emplace_back(phase, h5::read_double_attr(s, name.c_str(), st));
    }
    return r;
  });
}

ResultsFrames read_results_frames(const std::filesystem::path& path) {
  return read_guarded(path, [&] {
    const std::string where = path.string();
    const h5::Handle file = open_results(path, where);
    const hid_t root = file.get();
    ResultsFrames f;
    f.frame = read_column<uint64_t>(root, where, "frame", H5T_NATIVE_UINT64);
    f.total_ms = read_column<double>(root, where, "t_total_ms", H5T_NATIVE_DOUBLE);
    f.pairs = read_column<uint64_t>(root, where, "pairs", H5T_NATIVE_UINT64);
    const size_t rows = f.frame.size();
    if (f.total_ms.size() != rows || f.pairs.size() != rows)
      fail(where + ": /frames: t_total_ms and pairs have other lengths than frame");
    // Files written before --repeat have neither column: one pass, no noise.
    f.repeats = H5Lexists(root, "frames/repeats", H5P_DEFAULT) > 0
                    ? read_column<uint64_t>(root, where, "repeats", H5T_NATIVE_UINT64)
                    : std::vector<uint64_t>(rows, 1);
    f.total_noise = H5Lexists(root, "frames/t_total_noise", H5P_DEFAULT) > 0
                        ? read_column<double>(root, where, "t_total_noise", H5T_NATIVE_DOUBLE)
                        : std::vector<double>(rows, 0.0);
    if (f.repeats.size() != rows || f.total_noise.size() != rows)
      fail(where + ": /frames: repeats and t_total_noise have other lengths than frame");
    if (H5Lexists(root, "frames/pairs_self", H5P_DEFAULT) > 0) {
      f.pairs_self = read_column<uint64_t>(root, where, "pairs_self", H5T_NATIVE_UINT64);
      f.pairs_inter = read_column<uint64_t>(root, where, "pairs_inter", H5T_NATIVE_UINT64);
      if (f.pairs_self.size() != rows || f.pairs_inter.size() != rows)
        fail(where + ": /frames: pairs_self and pairs_inter have other lengths than frame");
    }
    return f;
  });
}

namespace {

// A (rows x passes) dataset of /passes as rows.
std::vector<std::vector<double>> read_pass_matrix(hid_t group, const std::string& name, const std::string& g,
                                                  uint64_t passes) {
  using h5::own;
  const std::string ds = g + "/" + name;
  h5::Handle d = own(H5Dopen2(group, name.c_str(), H5P_DEFAULT), H5Dclose, ds, "open dataset");
  h5::Handle space = own(H5Dget_space(d.get()), H5Sclose, ds, "get dataspace");
  if (H5Sget_simple_extent_ndims(space.get()) != 2) fail(ds + ": not a two-dimensional dataset (frames x passes)");
  hsize_t dims[2] = {0, 0};
  h5::check(H5Sget_simple_extent_dims(space.get(), dims, nullptr), ds, "get size");
  if (dims[1] != passes)
    fail(ds + ": " + std::to_string(dims[1]) + " columns, the group's passes attribute says " +
         std::to_string(passes));
  std::vector<double> flat(dims[0] * dims[1]);
  if (!flat.empty())
    h5::check(H5Dread(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, flat.data()), ds, "read");
  std::vector<std::vector<double>> rows(dims[0]);
  for (hsize_t i = 0; i < dims[0]; ++i)
    rows[i].assign(flat.begin() + ptrdiff_t(i * dims[1]), flat.begin() + ptrdiff_t((i + 1) * dims[1]));
  return rows;
}

}  // namespace

ResultsPasses read_results_passes(const std::filesystem::path& path) {
  return read_guarded(path, [&] {
    const std::string where = path.string();
    const h5::Handle file = open_results(path, where);
    const hid_t root = file.get();
    ResultsPasses r;
    if (H5Lexists(root, "passes", H5P_DEFAULT) <= 0) return r;
    const std::string g = where + ": /passes";
    h5::Handle group = h5::own(H5Gopen2(root, "passes", H5P_DEFAULT), H5Gclose, g, "open group");
    const int64_t passes = h5::read_int_attr(group.get(), "passes", g);
    if (passes < 1) fail(g + ": passes attribute " + std::to_string(passes) + ", expected at least 1");
    r.passes = uint64_t(passes);
    r.total_ms = read_pass_matrix(group.get(), "t_total_ms", g, r.passes);
    const h5::Handle frame = h5::own(H5Dopen2(root, "frames/frame", H5P_DEFAULT), H5Dclose, where + ": /frames/frame",
                                     "open dataset");
    const hsize_t rows = rows_of(frame.get(), where + ": /frames/frame");
    if (r.total_ms.size() != rows)
      fail(g + "/t_total_ms: " + std::to_string(r.total_ms.size()) + " rows, /frames has " + std::to_string(rows));
    for (size_t p = 0; p < kPhaseCount; ++p) {
      const std::string name = std::string("t_") + kPhaseNames[p] + "_ms";
      if (H5Lexists(group.get(), name.c_str(), H5P_DEFAULT) <= 0) continue;
      r.phase_ms.emplace_back(kPhaseNames[p], read_pass_matrix(group.get(), name, g, r.passes));
      if (r.phase_ms.back().second.size() != rows)
        fail(g + "/" + name + ": " + std::to_string(r.phase_ms.back().second.size()) + " rows, /frames has " +
             std::to_string(rows));
    }
    return r;
  });
}

ResultsPlans read_results_plans(const std::filesystem::path& path) {
  return read_guarded(path, [&] {
    const std::string where = path.string();
    const h5::Handle file = open_results(path, where);
    const hid_t root = file.get();
    ResultsPlans plans;
    plans.pipeline = h5::read_string_attr(root, "pipeline", where + ": /");
    if (H5Lexists(root, "plans", H5P_DEFAULT) <= 0) return plans;
    const std::vector<uint64_t> pass = read_column<uint64_t>(root, where, "pass", H5T_NATIVE_UINT64, "plans");
    const std::vector<uint64_t> frame = read_column<uint64_t>(root, where, "frame", H5T_NATIVE_UINT64, "plans");
    const std::vector<uint64_t> inspect = read_column<uint64_t>(root, where, "inspect", H5T_NATIVE_UINT64, "plans");
    // Files written before plans recorded their probes have no probe column.
    const bool records_probes = H5Lexists(root, "plans/probe", H5P_DEFAULT) > 0;
    const std::vector<uint64_t> probe = records_probes
                                            ? read_column<uint64_t>(root, where, "probe", H5T_NATIVE_UINT64, "plans")
                                            : std::vector<uint64_t>(pass.size(), 0);
    const std::vector<std::string> trees = read_text_column(root, where, "trees", "plans");
    const std::vector<std::string> decision = read_text_column(root, where, "decision", "plans");
    std::vector<std::vector<std::string>> ops;
    for (Query q : kQueries) ops.push_back(read_text_column(root, where, query_name(q), "plans"));
    const size_t rows = pass.size();
    bool same_length = frame.size() == rows && inspect.size() == rows && probe.size() == rows && trees.size() == rows &&
                       decision.size() == rows;
    for (const auto& column : ops) same_length = same_length && column.size() == rows;
    if (!same_length) fail(where + ": /plans: its columns have different lengths");
    for (size_t i = 0; i < rows; ++i) {
      const std::string row = where + ": /plans row " + std::to_string(i) + " (pass " + std::to_string(pass[i]) +
                              ", frame " + std::to_string(frame[i]) + ")";
      if (pass[i] > plans.passes.size() || (pass[i] + 1 < plans.passes.size()))
        fail(row + ": the rows are not in pass order");
      if (pass[i] == plans.passes.size())
        plans.passes.push_back(
            {where + " (pipeline " + plans.pipeline + ", pass " + std::to_string(pass[i]) + ")", {}, records_probes});
      RecordedPlan& plan = plans.passes.back();
      if (frame[i] > UINT32_MAX || (!plan.frames.empty() && frame[i] != plan.frames.back().frame + 1))
        fail(row + ": the frames of a pass are not consecutive");
      // The row as a plan file's fields, read by the plan file's parser.
      std::string fields = trees[i];
      for (Query q : kQueries)
        if (!ops[size_t(q)][i].empty()) fields += std::string(" ") + query_name(q) + "=" + ops[size_t(q)][i];
      if (!decision[i].empty()) fields += " decision=" + decision[i];
      if (inspect[i]) fields += " inspect";
      if (probe[i]) fields += " probe";
      plan.frames.push_back({uint32_t(frame[i]), parse_plan_step(fields, row), 0});
    }
    return plans;
  });
}

}  // namespace cdb
