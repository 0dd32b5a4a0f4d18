#include "cell_status.h"

#include <string.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"

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
  // Written whole to a temporary name and renamed, so a reader never sees half a file.
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) fail(tmp.string() + ": cannot write cell status");
  }
  std::filesystem::rename(tmp, file);
}

std::optional<CellStatus> read_cell_status(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) return std::nullopt;
  const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
  if (!j.is_object() || !j.contains("cell") || !j.contains("state")) return std::nullopt;
  CellStatus s;
  s.cell = j.value("cell", "");
  s.scene = j.value("scene", "");
  s.pipeline = j.value("pipeline", "");
  s.device = j.value("device", "");
  s.state = j.value("state", "");
  s.exit_code = j.value("exit_code", -1);
  s.signal = j.value("signal", 0);
  s.seconds = j.value("seconds", 0.0);
  s.command = j.value("command", "");
  s.log = j.value("log", "");
  s.log_tail = j.value("log_tail", "");
  s.job = j.value("job", "");
  s.host = j.value("host", "");
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
