#pragma once
// The exit status of every cdbench command (docs/usage.md, "Exit codes").
namespace cdb {

inline constexpr int kExitOk = 0;
// The command ran and failed: bad scene data, an I/O error, a verify mismatch, failed
// sweep cells.
inline constexpr int kExitFailure = 1;
// The command line cannot be accepted (unknown option or name, malformed or conflicting
// values); found before any work starts.
inline constexpr int kExitUsage = 2;
// A run stopped by a signal exits 128 + its number (130 for SIGINT, 143 for SIGTERM).

}  // namespace cdb
