#pragma once
// Checks a results file's path (run --out) before any work, so a path that cannot be
// written fails with a sentence naming it rather than at the end of a long run or with the
// HDF5 library's error stack.
#include <string>

namespace cdb {

// Throws UsageError when `path` names a directory (ends in '/' or exists as one) or a file
// that exists while `overwrite` is false (--overwrite), Error when its directory cannot be
// created or is not writable. Creates the directory. Returns whether the file exists (a
// run then writes beside it and replaces it only once complete: io/results_file.h).
bool check_output_path(const std::string& path, bool overwrite);

}  // namespace cdb
