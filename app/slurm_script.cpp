#include "slurm_script.h"
#include "number_checks.h"

#include <cctype>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "cell_status.h"
#include "cdbench/core/error.h"

namespace cdb {
namespace {

namespace fs = std::filesystem;

// Slurm's time formats (sbatch --time): minutes, minutes:seconds, hours:minutes:seconds,
// days-hours, days-hours:minutes, days-hours:minutes:seconds, or no limit.
std::string check_time(const std::string& t) {
  static const std::regex format(R"(\d+(:\d+){0,2}|\d+-\d+(:\d+){0,2}|UNLIMITED|INFINITE)");
  return std::regex_match(t, format) ? "" : "not a Slurm time limit (M, H:M:S, D-H, D-H:M:S or UNLIMITED): " + t;
}

// Partition, account and gres values go on #SBATCH lines, which sbatch splits at spaces.
std::string check_word(const std::string& v) {
  for (char c : v)
    if (!std::isalnum(static_cast<unsigned char>(c)) && std::string_view("._-:,+=/").find(c) == std::string_view::npos)
      return "'" + v + "': only letters, digits and ._-:,+=/ are allowed";
  return v.empty() ? "must not be empty" : "";
}

std::string json_text(const std::string& s) {
  return nlohmann::json(s).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// The status fields a task knows before it runs, as a JSON object's members, so the script
// writes valid JSON whatever the scene path or command line holds.
std::string status_fields(const CellStatus& s) {
  return "\"cell\": " + json_text(s.cell) + ", \"scene\": " + json_text(s.scene) + ", \"pipeline\": " +
         json_text(s.pipeline) + ", \"device\": " + json_text(s.device) + ", \"command\": " + json_text(s.command) +
         ", \"log\": " + json_text(s.log);
}

std::string job_name(const std::string& sweep_file) {
  std::string name = "cdbench-";
  for (char c : fs::path(sweep_file).stem().string())
    name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return name;
}

}  // namespace

void add_slurm_options(CLI::App& sweep, SlurmOptions& o) {
  CLI::Option* script = sweep.add_option(
      "--slurm", o.script, "write a Slurm job-array script (one task per cell not complete) instead of running");
  const std::string group = "Slurm (with --slurm; sbatch's own options override them)";
  sweep.add_option("--time", o.time, "time limit of each array task, i.e. of one cell (sbatch --time)")
      ->check(check_time, "TIME")
      ->needs(script)
      ->group(group)
      ->capture_default_str();
  sweep.add_option("--cpus-per-task", o.cpus_per_task, "CPUs for each cell, also its OpenMP threads")
      ->check(whole_in(1, 4096))
      ->needs(script)
      ->group(group)
      ->capture_default_str();
  sweep.add_option("--partition", o.partition, "partition (default: the cluster's default)")
      ->check(check_word, "NAME")
      ->needs(script)
      ->group(group);
  sweep.add_option("--account", o.account, "account to charge (default: yours)")
      ->check(check_word, "NAME")
      ->needs(script)
      ->group(group);
  sweep.add_option("--gres", o.gres,
                   "generic resources when some cell runs on cuda, e.g. gpu:h100:1; none for no request")
      ->check(check_word, "GRES")
      ->needs(script)
      ->group(group)
      ->capture_default_str();
  sweep.add_option("--throttle", o.throttle, "at most this many cells at once (--array=...%N); 0: no limit")
      ->needs(script)
      ->group(group)
      ->capture_default_str();
}

SlurmScript write_slurm_script(const SweepPlan& plan, const SweepRunOptions& run, const SlurmOptions& slurm) {
  std::vector<const SweepCell*> cells;
  for (const auto& c : plan.cells)
    if (!cell_complete(run.out_dir, c)) cells.push_back(&c);
  const fs::path dir = fs::absolute(run.out_dir);
  const fs::path script = fs::absolute(slurm.script);
  const std::string exe = fs::read_symlink("/proc/self/exe").string();
  bool gpu = false;
  for (const SweepCell* c : cells) gpu = gpu || c->device == "cuda";

  std::ostringstream s;
  s << "#!/bin/bash\n";
  if (cells.empty()) {
    s << "# Written by cdbench sweep " << plan.file << ": every cell was complete then; nothing to run.\n"
      << "echo " << shell_quote("cdbench sweep " + plan.file + ": every cell complete in " + dir.string()) << "\n";
  } else {
    s << "# Written by cdbench sweep " << plan.file << ":\n"
      << "# one array task per cell whose results were not complete then (" << cells.size() << " of "
      << plan.cells.size() << ").\n"
      << "# Each task marks its cell running in <cell>.status.json, runs its cdbench run line with\n"
      << "# the output in logs/<cell>.log, and records how it ended there for cdbench report.\n"
      << "# sbatch options given on the command line override the ones here, e.g.\n"
      << "# sbatch --time=2:00:00 FILE.\n"
      << "#SBATCH --job-name=" << job_name(plan.file) << "\n"
      << "#SBATCH --array=0-" << cells.size() - 1;
    if (slurm.throttle) s << "%" << slurm.throttle;
    s << "\n#SBATCH --time=" << slurm.time << "\n"
      << "#SBATCH --cpus-per-task=" << slurm.cpus_per_task << "\n";
    if (!slurm.partition.empty()) s << "#SBATCH --partition=" << slurm.partition << "\n";
    if (!slurm.account.empty()) s << "#SBATCH --account=" << slurm.account << "\n";
    if (gpu && slurm.gres != "none") s << "#SBATCH --gres=" << slurm.gres << "\n";
    s << "#SBATCH --chdir=" << shell_quote(dir.string()) << "\n"
      << "#SBATCH --output=" << shell_quote((dir / "logs" / "slurm-%A_%a.out").string()) << "\n"
      << "set -u\n"
      << "dir=" << shell_quote(dir.string()) << "\n"
      << "case ${SLURM_ARRAY_TASK_ID:?run this with sbatch} in\n";
    for (size_t i = 0; i < cells.size(); ++i) {
      const SweepCell& c = *cells[i];
      s << "  " << i << ") cell=" << c.name << "\n"
        << "     fields=" << shell_quote(status_fields(status_of(plan, c, run))) << "\n"
        << "     cmd=(" << shell_quote(exe) << " " << shell_line(cell_run_args(plan, c, dir, run.scenes_dir)) << ") ;;\n";
    }
    s << "  *) echo \"no cell for array task $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\n"
      << "esac\n"
      << "export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-" << slurm.cpus_per_task << "}\n"
      << "job=\"slurm job ${SLURM_ARRAY_JOB_ID:-${SLURM_JOB_ID:-}}_$SLURM_ARRAY_TASK_ID\"\n"
      << "host=$(hostname -s)\n"
      << "log=$dir/logs/$cell.log\n"
      << "status() {  # status STATE EXIT SIGNAL TAIL: <cell>.status.json, written whole, then renamed\n"
      << "  printf '{%s, \"state\": \"%s\", \"exit_code\": %d, \"signal\": %d, \"seconds\": %d, \"job\": \"%s\", "
         "\"host\": \"%s\", \"log_tail\": \"%s\"}\\n' \\\n"
      << "    \"$fields\" \"$1\" \"$2\" \"$3\" $((SECONDS - start)) \"$job\" \"$host\" \"$4\" >\"$dir/$cell.status.json.tmp\" &&\n"
      << "    mv -f \"$dir/$cell.status.json.tmp\" \"$dir/$cell.status.json\"\n"
      << "}\n"
      << "# At its time limit or on scancel, Slurm sends SIGTERM to every process of the task: the\n"
      << "# cell closes its results file as incomplete, and this trap keeps the script alive to record it.\n"
      << "trap : TERM\n"
      << "start=$SECONDS\n"
      << "rm -f \"$dir/$cell.h5\"\n"
      << "status running -1 0 ''\n"
      << "\"${cmd[@]}\" >\"$log\" 2>&1\n"
      << "rc=$?\n"
      << "state=failed; [[ $rc -eq 0 ]] && state=complete\n"
      << "sig=0; [[ $rc -gt 128 && $rc -ne 130 && $rc -ne 143 ]] && sig=$((rc - 128))\n"
      << "status $state $((sig ? -1 : rc)) $sig \"$(tail -n 1 \"$log\" | tr -d '\\\\\"' | tr -c '[:print:]' ' ')\"\n"
      << "exit $rc\n";
  }

  // slurmstepd opens --output and enters --chdir on the node before the script runs, so
  // both must exist already.
  fs::create_directories(dir / "logs");
  if (script.has_parent_path()) fs::create_directories(script.parent_path());
  std::ofstream out(script);
  out << s.str();
  if (!out) fail(script.string() + ": cannot write the Slurm script");
  out.close();
  fs::permissions(script, fs::perms::owner_exec | fs::perms::group_exec | fs::perms::others_exec,
                  fs::perm_options::add);

  SlurmScript written;
  written.tasks = cells.size();
  for (size_t i = 0; i < cells.size(); ++i) {
    const fs::path status_file = cell_status_file(dir, cells[i]->name);
    if (const auto earlier = read_cell_status(status_file); earlier && cell_in_progress(*earlier))
      ++written.in_progress;
    CellStatus pending = status_of(plan, *cells[i], run);
    pending.state = "pending";
    pending.job = "task " + std::to_string(i) + " of " + script.string();
    write_cell_status(status_file, pending);
  }
  return written;
}

int slurm_script_command(const SweepPlan& plan, const SweepRunOptions& run, const SlurmOptions& slurm) {
  const SlurmScript written = write_slurm_script(plan, run, slurm);
  const std::string& file = slurm.script;
  if (written.tasks == 0) {
    std::printf("wrote %s: every cell of %s is complete in %s; nothing to submit\n", file.c_str(), plan.file.c_str(),
                run.out_dir.string().c_str());
    return 0;
  }
  std::printf("wrote %s: %zu array tasks (%zu cells already complete); submit with sbatch %s\n", file.c_str(),
              written.tasks, plan.cells.size() - written.tasks, file.c_str());
  if (written.in_progress)
    std::printf("note: %zu of these cells were pending or running under an earlier script or sweep; cancel that job "
                "first (scancel) or they run twice\n",
                written.in_progress);
  return 0;
}

}  // namespace cdb
