#pragma once
// Checks a results file's path (run --out) before any work, so a path that cannot be
// written fails with a sentence naming it rather than at the end of a long run or with the
// HDF5 library's error stack, and claims it for this run (output_lock.h).
#include <string>

#include "output_lock.h"

namespace cdb {

struct OutputClaim {
  // Whether the file exists (a run then writes beside it and replaces it only once
  // complete: harness/results/results_file.h).
  bool existed = false;
  OutputLock lock;  // held until the run ends
};

// Throws UsageError when `path` names a directory (ends in '/' or exists as one), a file
// that exists while `overwrite` is false (--overwrite), or a file another run is writing;
// Error when its directory cannot be created or is not writable. Creates the directory.
OutputClaim check_output_path(const std::string& path, bool overwrite);

// An output file a command simply replaces (picture --out): a usage error when `path` names
// a directory (the message suggests `example` in it), Error when its directory cannot be
// created or the file cannot be written. Creates the directory.
void check_replaced_output(const std::string& path, const std::string& example);

}  // namespace cdb
