#pragma once
// After a write of a results file failed (a full disk, a file size limit), what is on disk
// is what HDF5 had flushed, partly overwritten by the writes that failed: sometimes a file
// `report` reads as incomplete, sometimes one it cannot read at all.
#include <filesystem>
#include <optional>

namespace cdb {

// Whether `report` can read `file`, asked of a fresh cdbench process: this one's HDF5
// library still holds the failed file open and would answer from its own cache. Empty when
// no process could be started to ask.
std::optional<bool> results_readable(const std::filesystem::path& file);

}  // namespace cdb
