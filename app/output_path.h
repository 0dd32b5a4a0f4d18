#pragma once
// Checks a results file's path (run --out) before any work, so a path that cannot be
// written fails with a sentence naming it rather than at the end of a long run or with the
// HDF5 library's error stack.
#include <string>

namespace cdb {

// Throws UsageError when `path` names a directory (ends in '/' or exists as one), Error
// when its directory cannot be created or is not writable. Creates the directory.
void check_output_path(const std::string& path);

}  // namespace cdb
