#include "cell_status.h"

#include <string.h>

#include <fstream>
#include <string>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"
#include "scenes/load/replace_file.h"

namespace cdb {

std::filesystem::path cell_status_file(const std::filesystem::path& out_dir, const std::string& cell) {
  return out_dir / (cell + ".status.json");
}

void write_cell_status(const std::filesystem::path& file, const CellStatus& s) {
  const nlohmann::json j = {{"cell", s.cell},         {"scene", s.scene},         {"pipeline", s.pipeline},
                            {"device", s.device},     {"state", s.state},         {"exit_code", s.exit_code},
                            {"signal", s.signal},     {"seconds", s.seconds},     {"command", s.command},
                            {"log", s.log},           {"log_tail", s.log_tail},   {"job", s.job},
                            {"host", s.host}};
  // Written whole and renamed into place, so a reader never sees half a file.
  const std::string failed = replace_file(file, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
  if (!failed.empty()) fail(failed + " (the cell's status)");
}

namespace {

template <class T>
constexpr const char* json_type_word() {
  if constexpr (std::is_same_v<T, std::string>)
    return "a string";
  else
    return "a number";
}

// The value of `key` in a status file (`fallback` when absent or null); a value of another
// type is refused naming the file and the key, since the sweep wrote it and its reading of
// the cell would be wrong.
template <class T>
T status_field(const nlohmann::json& j, const char* key, T fallback, const std::filesystem::path& file) {
  const auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  const bool fits = std::is_same_v<T, std::string> ? it->is_string() : it->is_number();
  if (!fits)
    fail(file.string() + ": \"" + key + "\" is " + it->dump() + " (a " + it->type_name() + "), not " +
         json_type_word<T>() + ": the sweep writes this file; remove it and run the sweep again to run the cell anew");
  return it->get<T>();
}

}  // namespace

std::optional<CellStatus> read_cell_status(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object() || !j.contains("cell") || !j.contains("state")) return std::nullopt;
  const auto text = [&](const char* key) { return status_field<std::string>(j, key, "", file); };
  CellStatus s;
  s.cell = text("cell");
  s.scene = text("scene");
  s.pipeline = text("pipeline");
  s.device = text("device");
  s.state = text("state");
  s.exit_code = status_field<int>(j, "exit_code", -1, file);
  s.signal = status_field<int>(j, "signal", 0, file);
  s.seconds = status_field<double>(j, "seconds", 0.0, file);
  s.command = text("command");
  s.log = text("log");
  s.log_tail = text("log_tail");
  s.job = text("job");
  s.host = text("host");
  return s;
}

std::string describe_exit(const CellStatus& s) {
  const char* abbrev = s.signal ? sigabbrev_np(s.signal) : nullptr;
  std::string d = !s.signal ? "exit " + std::to_string(s.exit_code)
                  : abbrev  ? std::string("killed by SIG") + abbrev
                            : "killed by signal " + std::to_string(s.signal);
  std::string tail = s.log_tail;
  // A usage error ends with CLI11's pointer to --help; the reason is the line before it.
  for (const std::string hint : {"\n", "Run with --help for more information.", "\n"})
    if (tail.ends_with(hint)) tail.resize(tail.size() - hint.size());
  while (!tail.empty() && tail.back() == '\n') tail.pop_back();
  const size_t nl = tail.rfind('\n');
  const std::string last = nl == std::string::npos ? tail : tail.substr(nl + 1);
  if (!last.empty()) d += ": " + last;
  return d;
}

bool cell_in_progress(const CellStatus& s) { return s.state == "pending" || s.state == "running"; }

std::string describe_progress(const CellStatus& s) {
  std::string where = s.job;
  if (!s.host.empty()) where += (where.empty() ? "on " : " on ") + s.host;
  return where.empty() ? s.state : s.state + " (" + where + ")";
}

}  // namespace cdb
