#include "harness/results/results_file.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "cdbench/core/build_info.h"
#include "cdbench/core/error.h"
#include "cdbench/core/phase.h"
#include "cdbench/core/utc_time.h"
#include "harness/results/results_columns.h"
#include "scenes/load/scene_label.h"

namespace cdb {
namespace {

using h5::check;
using h5::own;
using h5::write_attr;

constexpr hsize_t kRowsPerChunk = 1024;
constexpr unsigned kDeflateLevel = 4;
// Often enough that a killed run loses little, rarely enough that rewriting a partly
// filled compressed chunk costs nothing measurable.
constexpr auto kFlushInterval = std::chrono::seconds(1);

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

bool deflate_available() {
  unsigned config = 0;
  return H5Zfilter_avail(H5Z_FILTER_DEFLATE) > 0 &&
         H5Zget_filter_info(H5Z_FILTER_DEFLATE, &config) >= 0 &&
         (config & H5Z_FILTER_CONFIG_ENCODE_ENABLED);
}

// Chunked, shuffled and deflated (when the library has zlib) storage of `rank` dimensions.
h5::Handle chunked_layout(int rank, const hsize_t* chunk, const std::string& where) {
  h5::Handle dcpl = own(H5Pcreate(H5P_DATASET_CREATE), H5Pclose, where, "create dataset properties");
  check(H5Pset_chunk(dcpl.get(), rank, chunk), where, "set chunking");
  if (deflate_available()) {
    check(H5Pset_shuffle(dcpl.get()), where, "set shuffle filter");
    check(H5Pset_deflate(dcpl.get(), kDeflateLevel), where, "set deflate filter");
  }
  return dcpl;
}

hid_t file_type_of(ColumnType t, hid_t text_type) {
  switch (t) {
    case ColumnType::u32: return H5T_STD_U32LE;
    case ColumnType::u64: return H5T_STD_U64LE;
    case ColumnType::f64: return H5T_IEEE_F64LE;
    case ColumnType::text: return text_type;
  }
  return H5T_IEEE_F64LE;
}

// Groups remember the order their members and attributes were made in, so readers list
// columns and statistics in the writer's order (frame, t_total_ms, phases, ...), not by name.
h5::Handle create_group(hid_t loc, const char* name, const std::string& where) {
  const std::string at = where + ": /" + name;
  h5::Handle gcpl = own(H5Pcreate(H5P_GROUP_CREATE), H5Pclose, at, "create group properties");
  check(H5Pset_link_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), at,
        "track link order");
  check(H5Pset_attr_creation_order(gcpl.get(), H5P_CRT_ORDER_TRACKED | H5P_CRT_ORDER_INDEXED), at,
        "track attribute order");
  return own(H5Gcreate2(loc, name, H5P_DEFAULT, gcpl.get(), H5P_DEFAULT), H5Gclose, at, "create group");
}

}  // namespace

ResultsFile::ResultsFile(const std::filesystem::path& path, const RunInfo& info, Placement placement)
    : target_(path),
      path_(placement == Placement::staged ? std::filesystem::path(path.string() + ".incomplete") : path),
      where_(path_.string()) {
  h5::silence_library_errors();
  // Checked before the file exists, so a bad value leaves no file behind.
  if (!info.scene_overrides.is_object())
    fail(where_ + ": scene_overrides: expected a JSON object, got " + info.scene_overrides.dump());
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) fail(where_ + ": cannot create directory " + path.parent_path().string() + ": " + ec.message());
  }
  try {
    create(info);
  } catch (const h5::IoError& e) {
    // Cut off while being made, it holds nothing of the run: removed, not left unreadable.
    forget_handles();
    std::error_code ec;
    std::filesystem::remove(path_, ec);
    io_failed(e);
  }
}

void ResultsFile::create(const RunInfo& info) {
  // Strong close degree: closing the file closes every object still open in it.
  h5::Handle fapl = own(H5Pcreate(H5P_FILE_ACCESS), H5Pclose, where_, "create file access properties");
  check(H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG), where_, "set close degree");
  // The 1.8 format on: its superblock and object headers carry checksums, so a damaged
  // file is refused by the reader rather than followed into a crash or an endless loop
  // (tests/test_input_mutations.cpp found both with the 1.0 format's unchecked metadata).
  check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_LATEST), where_, "set format version");
  file_ = own(H5Fcreate(where_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose, where_,
              "create results file");

  const hid_t root = file_.get();
  const std::string at = where_ + ": /";
  const BuildInfo& b = build_info();
  write_attr(root, "status", "incomplete", at);
  write_attr(root, "schema_version", kResultsSchemaVersion, at);
  write_attr(root, "cdbench_version", CDBENCH_VERSION, at);
  write_attr(root, "git_sha", b.git_sha, at);
  write_attr(root, "build_type", b.build_type, at);
  write_attr(root, "compiler", b.cxx_compiler, at);
  write_attr(root, "cuda_compiler", b.cuda_compiler, at);
  write_attr(root, "scene", info.scene, at);
  write_attr(root, "scene_description", info.scene_description, at);
  write_attr(root, "scene_overrides", info.scene_overrides.dump(), at);
  write_attr(root, "scene_label", scene_label(info.scene, info.scene_overrides), at);
  write_attr(root, "pipeline", info.pipeline, at);
  write_attr(root, "label", info.label, at);
  write_attr(root, "input_path", info.input_path, at);
  write_attr(root, "backend", info.backend, at);
  write_attr(root, "device_name", info.device_name, at);
  write_attr(root, "driver_version", int64_t(info.driver_version), at);
  write_attr(root, "runtime_version", int64_t(info.runtime_version), at);
  write_attr(root, "precision", info.precision, at);
  write_attr(root, "precision_warning", info.precision_warning, at);
  write_attr(root, "params_json", info.params_json, at);
  write_attr(root, "warmup", uint64_t(info.warmup), at);
  write_attr(root, "frame_first", uint64_t(info.frame_first), at);
  write_attr(root, "frame_last", uint64_t(info.frame_last), at);
  write_attr(root, "triangles", info.triangles, at);
  write_attr(root, "vertices", info.vertices, at);
  write_attr(root, "copy_bandwidth_gbps", info.copy_gbps, at);
  write_attr(root, "cold", uint64_t(info.cold), at);
  write_attr(root, "contact_distance", info.contact_distance, at);
  write_attr(root, "contact_substeps", uint64_t(info.contact_substeps), at);
  write_attr(root, "repeat_plan", info.repeat_plan, at);
  write_attr(root, "plan_source", info.plan_source, at);
  write_attr(root, "host", host_name(), at);
  write_attr(root, "cpu_model", info.cpu_model, at);
  write_attr(root, "host_cores", info.host_cores, at);
  write_attr(root, "omp_threads", info.omp_threads, at);
  write_attr(root, "host_busy_before", info.host_busy_before, at);
  host_warning_ = info.host_warning;
  write_attr(root, "host_warning", host_warning_, at);
  write_attr(root, "created_utc", utc_now(), at);

  text_type_ = own(H5Tcopy(H5T_C_S1), H5Tclose, where_, "copy string type");
  check(H5Tset_size(text_type_.get(), kTextColumnBytes), where_, "set string size");
  check(H5Tset_strpad(text_type_.get(), H5T_STR_NULLPAD), where_, "set string padding");

  phase_timing_ = info.phase_timing;
  frames_ = create_group(root, "frames", where_);
  columns_ = create_columns(frames_.get(), "frames", frame_columns());
  check(H5Fflush(root, H5F_SCOPE_GLOBAL), where_, "flush");
  last_flush_ = std::chrono::steady_clock::now();
}

template <class Write>
void ResultsFile::writing(const std::string& what, Write write) {
  if (!file_) fail(where_ + ": " + what + (what.empty() ? "" : ": ") + "the results file is already closed");
  try {
    write();
  } catch (const h5::IoError& e) {
    io_failed(e);
  }
}

void ResultsFile::append_frame(uint32_t frame, const FrameStats& stats, const MemoryStats& memory) {
  const std::string row = "frame " + std::to_string(frame);
  writing(row, [&] {
    const FrameRow values{frame, stats, memory};
    if (stats.query_pairs) {
      if (query_pair_columns_.empty()) {
        if (rows_ > 0) fail(where_ + ": /frames " + row + ": pairs by query from this frame on only");
        query_pair_columns_ = create_columns(frames_.get(), "frames", query_pair_columns());
      }
      uint64_t query_rows = rows_;
      append_row(query_pair_columns(), query_pair_columns_, query_rows, values, "frames", row);
    } else if (!query_pair_columns_.empty()) {
      fail(where_ + ": /frames " + row + ": no pairs by query, where earlier frames have them");
    }
    append_row(frame_columns(), columns_, rows_, values, "frames", row);
  });
}

template <class Row>
std::vector<h5::Handle> ResultsFile::create_columns(hid_t group, const std::string& group_name,
                                                    const std::vector<TableColumn<Row>>& cols) {
  std::vector<h5::Handle> datasets;
  const hsize_t empty = 0, unlimited = H5S_UNLIMITED, chunk = kRowsPerChunk;
  for (const TableColumn<Row>& c : cols) {
    const std::string ds = where_ + ": /" + group_name + "/" + c.name;
    h5::Handle space = own(H5Screate_simple(1, &empty, &unlimited), H5Sclose, ds, "create dataspace");
    h5::Handle dcpl = chunked_layout(1, &chunk, ds);
    datasets.push_back(own(H5Dcreate2(group, c.name.c_str(), file_type_of(c.type, text_type_.get()), space.get(),
                                      H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                           H5Dclose, ds, "create dataset"));
    write_attr(datasets.back().get(), "description", c.description, ds);
  }
  return datasets;
}

template <class Row>
void ResultsFile::append_row(const std::vector<TableColumn<Row>>& cols, std::vector<h5::Handle>& datasets,
                             uint64_t& rows, const Row& row, const std::string& group, const std::string& row_name) {
  const hsize_t size = rows + 1, start = rows, one = 1;
  h5::Handle mem_space = own(H5Screate_simple(1, &one, nullptr), H5Sclose, where_, "create dataspace");
  for (size_t i = 0; i < cols.size(); ++i) {
    const std::string at = where_ + ": /" + group + "/" + cols[i].name + " " + row_name;
    const hid_t ds = datasets[i].get();
    check(H5Dset_extent(ds, &size), at, "extend dataset");
    h5::Handle file_space = own(H5Dget_space(ds), H5Sclose, at, "get dataspace");
    check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, &start, nullptr, &one, nullptr), at,
          "select row");
    // The value in the memory type HDF5 converts to the column's.
    const ColumnValue v = cols[i].value(row);
    uint32_t narrow = 0;
    char cell[kTextColumnBytes] = {};
    hid_t type = H5T_NATIVE_UINT64;
    const void* data = std::get_if<uint64_t>(&v);
    if (cols[i].type == ColumnType::u32) {
      const uint64_t x = std::get<uint64_t>(v);
      if (x > std::numeric_limits<uint32_t>::max()) fail(at + ": value " + std::to_string(x) + " does not fit 32 bits");
      narrow = uint32_t(x), type = H5T_NATIVE_UINT32, data = &narrow;
    } else if (cols[i].type == ColumnType::f64) {
      type = H5T_NATIVE_DOUBLE, data = &std::get<double>(v);
    } else if (cols[i].type == ColumnType::text) {
      const std::string& text = std::get<std::string>(v);
      if (text.size() > kTextColumnBytes)
        fail(at + ": '" + text + "' is longer than " + std::to_string(kTextColumnBytes) + " bytes");
      text.copy(cell, text.size());
      type = text_type_.get(), data = cell;
    }
    check(H5Dwrite(ds, type, mem_space.get(), file_space.get(), H5P_DEFAULT, data), at, "write");
  }
  ++rows;
  flush_now_and_then();
}

void ResultsFile::append_plan_step(uint32_t pass, uint32_t frame, const PlanStep& step) {
  const std::string row = "pass " + std::to_string(pass) + " frame " + std::to_string(frame);
  writing(row, [&] {
    if (!plans_) {
      plans_ = create_group(file_.get(), "plans", where_);
      write_attr(plans_.get(), "description",
                 "front pipelines: per pass over the frames and per frame, what the frame ran (its plan step)",
                 where_ + ": /plans");
      plan_columns_ = create_columns(plans_.get(), "plans", plan_columns());
    }
    append_row(plan_columns(), plan_columns_, plan_rows_, PlanRow{pass, frame, step}, "plans", row);
  });
}

void ResultsFile::append_passes(uint32_t frame, const std::vector<FrameTiming>& passes) {
  const std::string row = "frame " + std::to_string(frame);
  writing(row, [&] {
    const std::string at = where_ + ": /passes " + row;
    if (passes.empty()) fail(at + ": no passes");
    if (!passes_) {
      passes_ = create_group(file_.get(), "passes", where_);
      const std::string g = where_ + ": /passes";
      write_attr(passes_.get(), "description",
                 "per /frames row (rows) and measured pass (columns, pass 0 first as in /plans): the frame's times",
                 g);
      write_attr(passes_.get(), "passes", uint64_t(passes.size()), g);
      pass_count_ = passes.size();
      // Without --phase-timing only the frame and its upload are timed: the other phases'
      // zeros would be no measurement.
      std::vector<std::pair<std::string, int>> cols = {{"t_total_ms", -1}};
      for (size_t p = 0; p < kPhaseCount; ++p)
        if (phase_timing_ || Phase(p) == Phase::upload)
          cols.emplace_back(std::string("t_") + kPhaseNames[p] + "_ms", int(p));
      const hsize_t empty[2] = {0, pass_count_}, maxdims[2] = {H5S_UNLIMITED, pass_count_};
      const hsize_t chunk[2] = {std::max<hsize_t>(1, kRowsPerChunk / pass_count_), pass_count_};
      for (const auto& [name, phase] : cols) {
        const std::string ds = g + "/" + name;
        h5::Handle space = own(H5Screate_simple(2, empty, maxdims), H5Sclose, ds, "create dataspace");
        h5::Handle dcpl = chunked_layout(2, chunk, ds);
        pass_columns_.push_back(own(H5Dcreate2(passes_.get(), name.c_str(), H5T_IEEE_F64LE, space.get(),
                                               H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
                                    H5Dclose, ds, "create dataset"));
        write_attr(pass_columns_.back().get(), "description",
                   phase < 0 ? "frame time without its upload in each pass, ms"
                             : std::string("time in phase ") + kPhaseNames[size_t(phase)] + " in each pass, ms",
                   ds);
        if (phase >= 0) pass_phases_.push_back(phase);
      }
    }
    if (passes.size() != pass_count_)
      fail(at + ": " + std::to_string(passes.size()) + " passes, the earlier rows " + std::to_string(pass_count_));
    const hsize_t size[2] = {pass_rows_ + 1, pass_count_}, start[2] = {pass_rows_, 0}, count[2] = {1, pass_count_};
    h5::Handle mem_space = own(H5Screate_simple(2, count, nullptr), H5Sclose, at, "create dataspace");
    std::vector<double> values(pass_count_);
    for (size_t c = 0; c < pass_columns_.size(); ++c) {
      for (size_t p = 0; p < pass_count_; ++p)
        values[p] = c == 0 ? passes[p].total_ms : passes[p].phase_ms[size_t(pass_phases_[c - 1])];
      const hid_t ds = pass_columns_[c].get();
      check(H5Dset_extent(ds, size), at, "extend dataset");
      h5::Handle file_space = own(H5Dget_space(ds), H5Sclose, at, "get dataspace");
      check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr), at, "select row");
      check(H5Dwrite(ds, H5T_NATIVE_DOUBLE, mem_space.get(), file_space.get(), H5P_DEFAULT, values.data()), at,
            "write");
    }
    ++pass_rows_;
    flush_now_and_then();
  });
}

void ResultsFile::write_pairs(uint32_t frame, const std::vector<PrimPair>& pairs) {
  writing("frame " + std::to_string(frame), [&] {
    if (!pairs_) {
      pairs_ = create_group(file_.get(), "pairs", where_);
      write_attr(pairs_.get(), "description",
                 "per frame: sorted pairs (a, b), a < b, of 0-based triangle indices in the input's face order",
                 where_ + ": /pairs");
    }
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04u", frame);
    const std::string at = where_ + ": /pairs/" + name;
    const hsize_t dims[2] = {pairs.size(), 2}, maxdims[2] = {H5S_UNLIMITED, 2};
    const hsize_t chunk[2] = {std::max<hsize_t>(1, std::min<hsize_t>(pairs.size(), 1 << 16)), 2};
    h5::Handle space = own(H5Screate_simple(2, dims, maxdims), H5Sclose, at, "create dataspace");
    h5::Handle dcpl = chunked_layout(2, chunk, at);
    h5::Handle ds = own(H5Dcreate2(pairs_.get(), name, H5T_STD_U32LE, space.get(), H5P_DEFAULT, dcpl.get(),
                                   H5P_DEFAULT),
                        H5Dclose, at, "create dataset");
    static_assert(sizeof(PrimPair) == 2 * sizeof(uint32_t), "pairs are written as (n, 2) uint32");
    if (!pairs.empty())
      check(H5Dwrite(ds.get(), H5T_NATIVE_UINT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, pairs.data()), at, "write");
    write_attr(ds.get(), "frame", uint64_t(frame), at);
    flush_now_and_then();
  });
}

void ResultsFile::write_summary(const RunSummary& s, const MemoryStats& memory) {
  const std::string at = where_ + ": /summary";
  h5::Handle g = H5Lexists(file_.get(), "summary", H5P_DEFAULT) > 0
                     ? own(H5Gopen2(file_.get(), "summary", H5P_DEFAULT), H5Gclose, at, "open group")
                     : create_group(file_.get(), "summary", where_);
  const hid_t loc = g.get();
  const double none = std::nan("");
  auto put_stat = [&](const std::string& prefix, const Stat& st) {
    write_attr(loc, (prefix + "_mean").c_str(), st.count ? st.mean : none, at);
    write_attr(loc, (prefix + "_median").c_str(), st.count ? st.median : none, at);
    write_attr(loc, (prefix + "_p95").c_str(), st.count ? st.p95 : none, at);
    write_attr(loc, (prefix + "_min").c_str(), st.count ? st.min : none, at);
    write_attr(loc, (prefix + "_frames").c_str(), uint64_t(st.count), at);
  };
  write_attr(loc, "frames", uint64_t(s.frames), at);
  write_attr(loc, "warmup", uint64_t(s.warmup), at);
  write_attr(loc, "measured_frames", uint64_t(s.total.count), at);
  write_attr(loc, "first_frame_ms", s.frames ? s.first_ms : none, at);
  write_attr(loc, "first_frame_op", s.first_op, at);
  put_stat("t_total_ms", s.total);
  for (size_t p = 0; p < kPhaseCount; ++p) put_stat(std::string("t_") + kPhaseNames[p] + "_ms", s.phase[p]);
  write_attr(loc, "pairs_mean", s.total.count ? s.pairs_mean : none, at);
  if (s.by_query) {
    write_attr(loc, "pairs_self_mean", s.total.count ? s.pairs_self_mean : none, at);
    write_attr(loc, "pairs_inter_mean", s.total.count ? s.pairs_inter_mean : none, at);
  }
  write_attr(loc, "query_reruns", uint64_t(s.query_reruns), at);
  write_attr(loc, "repeats", uint64_t(s.repeats), at);
  write_attr(loc, "noise_median", s.noise_median, at);
  write_attr(loc, "host_syncs_mean", s.host_syncs_mean, at);
  write_attr(loc, "host_syncs_max", uint64_t(s.host_syncs_max), at);
  write_attr(loc, "bytes_floor_mean", s.bytes_floor_mean, at);
  write_attr(loc, "decisions_refit", uint64_t(s.decided_refit), at);
  write_attr(loc, "decisions_restructure", uint64_t(s.decided_restructure), at);
  write_attr(loc, "decisions_rebuild", uint64_t(s.decided_rebuild), at);
  write_attr(loc, "plan_mixed_frames", uint64_t(s.plan_mixed_frames), at);
  write_attr(loc, "warmup_frames", s.warmup_frames, at);
  write_attr(loc, "checked_frames", uint64_t(s.checked_frames), at);
  write_attr(loc, "recall_min", s.checked_frames ? s.recall_min : none, at);
  write_attr(loc, "precision_min", s.checked_frames ? s.precision_min : none, at);
  write_attr(loc, "missed", uint64_t(s.missed), at);
  write_attr(loc, "false_positives", uint64_t(s.false_positives), at);
  write_attr(loc, "contacts", uint64_t(s.contacts), at);
  write_attr(loc, "checked_pairs", uint64_t(s.checked_pairs), at);
  write_attr(loc, "contact_precision", s.checked_frames ? s.contact_precision : none, at);
  write_attr(loc, "contact_precision_min", s.checked_frames ? s.contact_precision_min : none, at);
  write_attr(loc, "discrete_missed_contacts", uint64_t(s.discrete_missed_contacts), at);
  write_attr(loc, "peak_bytes", uint64_t(memory.peak_bytes), at);
  write_attr(loc, "allocations", uint64_t(memory.allocations), at);
  write_attr(loc, "growths", uint64_t(memory.growths), at);
  write_memory(memory);
}

// /memory: what each buffer held at the peak, written with the summary (again, whole, where
// an abandoned run's summary follows a written one).
void ResultsFile::write_memory(const MemoryStats& memory) {
  if (H5Lexists(file_.get(), "memory", H5P_DEFAULT) > 0)
    check(H5Ldelete(file_.get(), "memory", H5P_DEFAULT), where_ + ": /memory", "delete group");
  h5::Handle g = create_group(file_.get(), "memory", where_);
  write_attr(g.get(), "description",
             "the executor's buffers at the run's memory peak, in the order they were first allocated "
             "(summary peak_bytes is their sum)",
             where_ + ": /memory");
  std::vector<h5::Handle> columns = create_columns(g.get(), "memory", memory_columns());
  uint64_t rows = 0;
  for (const BufferBytes& b : memory.at_peak)
    append_row(memory_columns(), columns, rows, MemoryRow{b}, "memory", b.buffer);
}

void ResultsFile::finish(const RunSummary& summary, const MemoryStats& memory, const RunFindings& findings) {
  writing("", [&] {
    write_summary(summary, memory);
    write_attr(file_.get(), "input_hash", findings.input_hash, where_ + ": /");
    write_attr(file_.get(), "noise_warning", findings.noise_warning, where_ + ": /");
    write_attr(file_.get(), "host_busy_after", findings.host_busy_after, where_ + ": /");
    const std::string warnings = host_warning_.empty() || findings.host_warning_after.empty()
                                     ? host_warning_ + findings.host_warning_after
                                     : host_warning_ + "; " + findings.host_warning_after;
    write_attr(file_.get(), "host_warning", warnings, where_ + ": /");
    for (const GpuAttribute& a : gpu_attributes()) {
      if (a.text) write_attr(file_.get(), a.name.c_str(), a.words(findings.gpu), where_ + ": /");
      else write_attr(file_.get(), a.name.c_str(), a.number(findings.gpu), where_ + ": /");
    }
    write_attr(file_.get(), "conditions", findings.poor_conditions.empty() ? "good" : "poor", where_ + ": /");
    write_attr(file_.get(), "conditions_notes", findings.poor_conditions, where_ + ": /");
    close("complete");
  });
  if (path_ == target_) return;
  // Complete: only now does it take the place of the file it replaces.
  std::error_code ec;
  std::filesystem::rename(path_, target_, ec);
  if (ec)
    fail("writing results to " + target_.string() + " failed: cannot rename the finished " + where_ +
         " over it: " + ec.message());
  path_ = target_;
  where_ = path_.string();
}

void ResultsFile::abandon(const RunSummary& summary, const MemoryStats& memory,
                          const std::string& error) noexcept {
  if (!file_) return;
  // Each step's failure is printed; after a system-side one nothing more can be written.
  const auto attempt = [&](auto step) {
    try {
      step();
    } catch (const h5::IoError& e) {
      broken_ = true;
      forget_handles();
      std::fprintf(stderr, "cdbench: writing results to %s failed: %s\n", where_.c_str(), e.reason.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "cdbench: %s\n", e.what());
    }
    return !broken_;
  };
  if (attempt([&] {
        write_attr(file_.get(), "error", error, where_ + ": /");
        write_summary(summary, memory);
      }))
    attempt([&] { close("incomplete"); });
}

void ResultsFile::close(const char* status) {
  const std::string at = where_ + ": /";
  write_attr(file_.get(), "closed_utc", utc_now(), at);
  write_attr(file_.get(), "status", status, at);
  columns_.clear();
  plan_columns_.clear();
  pass_columns_.clear();
  for (h5::Handle* h : {&pairs_, &plans_, &passes_, &frames_, &text_type_}) h->reset();
  // Closed once: the id is gone whether or not HDF5 reports a failure.
  check(file_.reset() ? 0 : -1, where_, "closing the results file");
}

void ResultsFile::io_failed(const h5::IoError& e) {
  broken_ = true;
  forget_handles();
  fail("writing results to " + where_ + " failed: " + e.reason);
}

void ResultsFile::forget_handles() noexcept {
  for (std::vector<h5::Handle>* columns : {&columns_, &plan_columns_, &pass_columns_}) {
    for (h5::Handle& c : *columns) c.abandon();
    columns->clear();
  }
  for (h5::Handle* h : {&pairs_, &plans_, &passes_, &frames_, &text_type_, &file_}) h->abandon();
}

void ResultsFile::flush_now_and_then() {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_flush_ < kFlushInterval) return;
  check(H5Fflush(file_.get(), H5F_SCOPE_GLOBAL), where_, "flush");
  last_flush_ = now;
}

}  // namespace cdb
