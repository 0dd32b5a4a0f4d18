#pragma once
// `cdbench report`: one row per results file, as a Markdown table, CSV or JSON. An incomplete
// file is a row that says so; a file that cannot be read is a row with the reason.
#include <string>
#include <vector>

namespace cdb {

// How the table is printed: Markdown for reading (rounded, the columns that say something
// for these files); CSV and JSON for scripts, with every column whatever the files and
// every number at full precision (JSON: one object per file, the CSV's columns as keys).
enum class ReportFormat { markdown, csv, json };

// Arguments are files or directories (every .h5 under them, plus the sweep cells recorded
// there without a results file: pending, running or failed rows). Prints the table on stdout; returns 1
// when some file could not be read, else 0.
int print_results_table(const std::vector<std::string>& files, ReportFormat format);

}  // namespace cdb
