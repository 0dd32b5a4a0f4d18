#pragma once
// Where one sweep cell stands, kept next to its results file as <cell>.status.json: pending
// (planned by a sweep or a Slurm script, not started), running, or how its process ended.
// The results file says how far the run got; this says how the process ended, which is all
// there is when it died before writing a results file.
#include <filesystem>
#include <optional>
#include <string>

namespace cdb {

struct CellStatus {
  std::string cell, scene, pipeline, device;
  std::string state;    // pending | running | complete | failed
  std::string job;      // what runs it: "slurm job 12_3", "pid 4711", or for a pending
                        // cell the Slurm script and array task that will
  std::string host;     // where it runs or ran; empty while pending
  int exit_code = -1;   // -1 when killed by a signal
  int signal = 0;       // the signal that killed it, 0 when it exited
  double seconds = 0;
  std::string command;  // the cdbench run line, shell-quoted
  std::string log;      // file with its stdout and stderr
  std::string log_tail; // last lines of that log
};

std::filesystem::path cell_status_file(const std::filesystem::path& out_dir, const std::string& cell);
void write_cell_status(const std::filesystem::path& file, const CellStatus& s);
// nullopt when the file is missing or not a cell status.
std::optional<CellStatus> read_cell_status(const std::filesystem::path& file);
// "exit 2", "killed by SIGKILL", with the log's last line when there is one.
std::string describe_exit(const CellStatus& s);
// True for pending and running: a process is to come or under way, none has ended.
bool cell_in_progress(const CellStatus& s);
// "pending (task 3 of /x/fig9.sbatch)", "running (slurm job 12_3 on node7)".
std::string describe_progress(const CellStatus& s);

}  // namespace cdb
