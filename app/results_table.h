#pragma once
// `cdbench report`: one row per results file, as a Markdown table or CSV. An incomplete
// file is a row that says so; a file that cannot be read is a row with the reason.
#include <string>
#include <vector>

namespace cdb {

// Arguments are files or directories (every .h5 under them, plus the sweep cells recorded
// there without a results file: pending, running or failed rows). Prints the table on stdout; returns 1
// when some file could not be read, else 0.
int print_results_table(const std::vector<std::string>& files, bool csv);

}  // namespace cdb
