#pragma once
// The exit status of every cdbench command: one table for all of them (docs/usage.md,
// "Exit codes", lists what each command exits with).
namespace cdb {

// Success, also --help and --version; report and compare with every input read.
inline constexpr int kExitOk = 0;
// The command ran and failed: bad scene data, an I/O error, a verify mismatch, failed
// sweep cells, a regression under compare --fail-on-regression, a results file that cannot
// be read (report, compare), report finding no results or a failed sweep cell.
inline constexpr int kExitFailure = 1;
// The command line cannot be accepted (unknown option or name, malformed or conflicting
// values, an invalid sweep file or sweep cell options); found before any work starts.
inline constexpr int kExitUsage = 2;
// A command stopped by signal N exits 128 + N (130 for SIGINT, 143 for SIGTERM).
inline constexpr int exit_for_signal(int signal) { return 128 + signal; }

}  // namespace cdb
