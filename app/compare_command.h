#pragma once
// `cdbench compare A B`: the runs of B against the matching runs of A (docs/usage.md,
// "Comparing runs"). Runs match on their identity: the scene (label and, where both files
// have it, the input's content hash), pipeline, device and every option that changes the
// pair set or how time is measured; a mismatch is a usage error unless --allow-mismatch.
// Repeats of one run (sweep cells _rK, or files of the same configuration) combine into
// one estimate with a 95% confidence interval (run_statistics.h).
#include <CLI/CLI.hpp>

#include <string>

namespace cdb {

struct CompareOptions {
  std::string a, b;  // results files or directories of them
  std::string metric = "mean";
  double threshold_pct = 5.0;
  bool csv = false, json = false;
  bool allow_mismatch = false;
  bool fail_on_regression = false;
};

CLI::App* add_compare_command(CLI::App& app, CompareOptions& c);

// 0, or 1 with --fail-on-regression when a row regresses (or when a file cannot be read);
// a mismatch without --allow-mismatch throws UsageError (exit 2).
int compare_command(const CompareOptions& c);

}  // namespace cdb
