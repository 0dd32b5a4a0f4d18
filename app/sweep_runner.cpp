#include "sweep_runner.h"
#include "damaged_file_guard.h"
#include "exit_codes.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

#include "cell_status.h"
#include "cdbench/core/error.h"
#include "cdbench/core/utc_time.h"
#include "interrupt.h"
#include "harness/results/results_reader.h"

extern char** environ;

namespace cdb {
namespace {

namespace fs = std::filesystem;

// The last lines of a log, at most about 2 KB: enough for the error without copying a
// log full of progress lines into the status file.
std::string log_tail(const fs::path& log) {
  std::ifstream in(log, std::ios::binary);
  if (!in) return "";
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff start = size > 2048 ? size - 2048 : 0;
  in.seekg(start);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (start > 0 && text.find('\n') != std::string::npos) text.erase(0, text.find('\n') + 1);
  size_t at = text.size(), lines = 0;
  if (at > 0 && text[at - 1] == '\n') --at;
  while (at > 0 && lines < 10) {
    const size_t nl = text.rfind('\n', at - 1);
    if (nl == std::string::npos) return text;
    at = nl;
    ++lines;
  }
  return lines < 10 ? text : text.substr(at + 1);
}

// GPU k of this process's visible ones: the k-th of CUDA_VISIBLE_DEVICES when it is set,
// so a sweep confined to some GPUs spreads over those.
std::string gpu_for_slot(unsigned slot) {
  const char* visible = std::getenv("CUDA_VISIBLE_DEVICES");
  if (!visible || !*visible) return std::to_string(slot);
  std::vector<std::string> ids;
  std::stringstream list(visible);
  for (std::string id; std::getline(list, id, ',');) ids.push_back(id);
  return slot < ids.size() ? ids[slot] : std::to_string(slot);
}

std::string host_name() {
  char name[256] = {};
  return gethostname(name, sizeof name - 1) == 0 ? name : "";
}

}  // namespace

CellStatus status_of(const SweepPlan& plan, const SweepCell& cell, const SweepRunOptions& options) {
  const fs::path dir = fs::absolute(options.out_dir);
  CellStatus s;
  s.cell = cell.name;
  s.scene = cell.scene_label;
  s.pipeline = cell.pipeline;
  s.device = cell.device;
  s.command = "cdbench " + shell_line(cell_run_args(plan, cell, dir, options.scenes_dir));
  s.log = (dir / "logs" / (cell.name + ".log")).string();
  return s;
}

namespace {

struct Running {
  size_t cell = 0;
  pid_t pid = 0;
  unsigned slot = 0;
  std::chrono::steady_clock::time_point start;
};

pid_t spawn_cell(const std::vector<std::string>& args, const fs::path& log, const std::string& gpu) {
  std::vector<std::string> env_text;
  for (char** e = environ; *e; ++e)
    if (gpu.empty() || std::string_view(*e).rfind("CUDA_VISIBLE_DEVICES=", 0) != 0) env_text.emplace_back(*e);
  if (!gpu.empty()) env_text.push_back("CUDA_VISIBLE_DEVICES=" + gpu);
  std::vector<char*> envp, argv;
  for (auto& e : env_text) envp.push_back(e.data());
  envp.push_back(nullptr);
  std::vector<std::string> words = args;
  words.insert(words.begin(), "cdbench");
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  pid_t pid = 0;
  // This very binary, so a cell runs the same build as the sweep that started it.
  const int err = posix_spawn(&pid, "/proc/self/exe", &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (err) fail("cannot start cdbench for " + log.string() + ": " + std::strerror(err));
  return pid;
}

}  // namespace

bool cell_complete(const fs::path& out_dir, const SweepCell& cell) {
  const fs::path file = cell_results_file(out_dir, cell);
  if (!fs::exists(file)) return false;
  try {
    const DamagedFileGuard guard("sweep", file.string());
    return read_results_overview(file).status == "complete";
  } catch (const std::exception&) {
    return false;
  }
}

void list_cells(const SweepPlan& plan, const SweepRunOptions& options, const std::vector<std::string>& option_errors) {
  size_t complete = 0, invalid = 0;
  for (size_t i = 0; i < plan.cells.size(); ++i) {
    const SweepCell& c = plan.cells[i];
    std::string state = "to run";
    if (i < option_errors.size() && !option_errors[i].empty()) {
      state = "INVALID: " + option_errors[i];
      ++invalid;
    } else if (cell_complete(options.out_dir, c)) {
      state = "complete (skipped)";
      ++complete;
    } else if (const auto s = read_cell_status(cell_status_file(options.out_dir, c.name)); s && s->state != "complete") {
      state = cell_in_progress(*s) ? "to run (" + describe_progress(*s) + ")"
                                   : "to run again (failed: " + describe_exit(*s) + ")";
    }
    std::printf("%3zu  %s  %s\n     cdbench %s\n", i, c.name.c_str(), state.c_str(),
                shell_line(cell_run_args(plan, c, options.out_dir, options.scenes_dir)).c_str());
  }
  std::printf("sweep %s: %zu cells, %zu complete, %zu to run", plan.file.c_str(), plan.cells.size(), complete,
              plan.cells.size() - complete - invalid);
  if (invalid) std::printf(", %zu invalid (run refuses them)", invalid);
  std::printf("\n");
}

int run_sweep(const SweepPlan& plan, const SweepRunOptions& options) {
  const fs::path& dir = options.out_dir;
  fs::create_directories(dir / "logs");
  std::ofstream sweep_log(dir / "sweep.log", std::ios::app);
  sweep_log << utc_now() << " start " << plan.file << ": " << plan.cells.size() << " cells, " << options.slots
            << " at a time" << std::endl;

  std::vector<size_t> todo;
  for (size_t i = 0; i < plan.cells.size(); ++i) {
    if (cell_complete(dir, plan.cells[i])) {
      std::printf("skip %s: results complete\n", plan.cells[i].name.c_str());
      sweep_log << utc_now() << " skip " << plan.cells[i].name << ": results complete" << std::endl;
    } else {
      todo.push_back(i);
    }
  }
  // Every cell to run is marked pending first, so `report DIR` shows the whole sweep while
  // it runs, and what an interruption left unstarted.
  for (size_t i : todo) {
    CellStatus pending = status_of(plan, plan.cells[i], options);
    pending.state = "pending";
    write_cell_status(cell_status_file(dir, pending.cell), pending);
  }
  std::printf("sweep %s: %zu cells, %zu already complete, %zu to run, %u at a time\n", plan.file.c_str(),
              plan.cells.size(), plan.cells.size() - todo.size(), todo.size(), options.slots);
  std::fflush(stdout);

  InterruptScope interrupt;
  int stopped_by = 0;
  size_t next = 0, done = 0, failed = 0;
  std::vector<std::optional<Running>> slots(options.slots);
  for (;;) {
    if (!stopped_by && interrupt.signal()) {
      stopped_by = interrupt.signal();
      // Children in our process group already got a Ctrl-C from the terminal; a signal
      // sent to this process alone is passed on so every cell ends its file cleanly.
      for (const auto& r : slots)
        if (r) kill(r->pid, stopped_by);
      std::printf("sweep: %s, waiting for the running cells; %zu not started\n", signal_name(stopped_by),
                  todo.size() - next);
      sweep_log << utc_now() << " " << signal_name(stopped_by) << ": " << todo.size() - next << " cells not started"
                << std::endl;
    }
    bool running = false;
    for (unsigned k = 0; k < slots.size(); ++k) {
      if (!slots[k] && !stopped_by && next < todo.size()) {
        const SweepCell& c = plan.cells[todo[next]];
        const fs::path file = cell_results_file(dir, c);
        // A stale incomplete file from an earlier attempt would be taken for this attempt's
        // if the new process died before writing its own.
        fs::remove(file);
        const std::string gpu = options.one_gpu_each ? gpu_for_slot(k) : "";
        const pid_t pid = spawn_cell(cell_run_args(plan, c, dir, options.scenes_dir), dir / "logs" / (c.name + ".log"), gpu);
        CellStatus running = status_of(plan, c, options);
        running.state = "running";
        running.job = "pid " + std::to_string(pid) + (gpu.empty() ? "" : ", gpu " + gpu);
        running.host = host_name();
        write_cell_status(cell_status_file(dir, c.name), running);
        slots[k] = Running{todo[next], pid, k, std::chrono::steady_clock::now()};
        sweep_log << utc_now() << " start " << c.name << " pid " << pid << (gpu.empty() ? "" : " gpu " + gpu) << std::endl;
        ++next;
      }
      running = running || slots[k];
    }
    if (!running) break;

    int wstatus = 0;
    const pid_t pid = waitpid(-1, &wstatus, WNOHANG);
    if (pid <= 0) {
      // Polling rather than blocking: the interrupt handler restarts system calls, and the
      // sweep must notice a signal while its children run.
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    for (auto& r : slots) {
      if (!r || r->pid != pid) continue;
      const SweepCell& c = plan.cells[r->cell];
      CellStatus s = status_of(plan, c, options);
      s.host = host_name();
      s.exit_code = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
      s.signal = WIFSIGNALED(wstatus) ? WTERMSIG(wstatus) : 0;
      s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - r->start).count();
      s.log_tail = log_tail(s.log);
      s.state = s.exit_code == 0 && cell_complete(dir, c) ? "complete" : "failed";
      write_cell_status(cell_status_file(dir, c.name), s);
      ++done;
      if (s.state == "complete") {
        std::printf("[%zu/%zu] %s: complete (%.1f s)\n", done, todo.size(), c.name.c_str(), s.seconds);
      } else {
        ++failed;
        std::printf("[%zu/%zu] %s: FAILED, %s (log %s)\n", done, todo.size(), c.name.c_str(), describe_exit(s).c_str(),
                    s.log.c_str());
      }
      std::fflush(stdout);
      sweep_log << utc_now() << " " << s.state << " " << c.name << " "
                << (s.state == "complete" ? "exit 0" : describe_exit(s)) << " " << s.seconds << " s" << std::endl;
      r.reset();
    }
  }
  std::printf("sweep: %zu run, %zu complete, %zu failed%s; results in %s\n", done, done - failed, failed,
              stopped_by ? ", stopped early" : "", dir.string().c_str());
  sweep_log << utc_now() << " end: " << done << " run, " << failed << " failed" << std::endl;
  if (stopped_by) return exit_for_signal(stopped_by);
  return failed ? kExitFailure : kExitOk;
}

}  // namespace cdb
