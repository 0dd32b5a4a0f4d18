#pragma once
// A file written whole under a temporary name beside it (FILE.part.PID) and renamed into
// place, so that a reader (another process, a later run) never sees half of one: the frame
// cache, an archive member's extraction, the frames descriptor, a sweep cell's status.
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>

namespace cdb {

// Writes `file` from what `write` puts on the stream (binary, truncating).
// Returns "" once the file is in place, else what went wrong, naming `file` and the
// system's reason; the temporary is removed either way. The caller decides what a failure
// costs: the caches warn and go on, the others fail.
std::string replace_file(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write);

}  // namespace cdb
