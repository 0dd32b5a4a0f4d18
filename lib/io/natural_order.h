#pragma once
// Natural order of file names: runs of digits compare as numbers, so frame2.obj comes
// before frame10.obj (plain text order puts f10 and f11 before f2).
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace cdb {

// Digit runs compare by value (leading zeros ignored), other characters by their byte
// value; names equal that way (f01, f1) fall back to text order, so the order is total.
bool natural_less(std::string_view a, std::string_view b);

// The file's extension in lower case (.OBJ -> .obj): the readers tell formats apart by it.
std::string lower_extension(const std::filesystem::path& file);

// The regular files of `dir` that `is_frame` accepts by name, in natural order. A link
// among them that leads nowhere (dangling, or a loop) is refused naming it, rather than
// leaving a gap in the frames; so is a directory that cannot be listed. Frames read
// through a link are fine.
std::vector<std::filesystem::path> frame_files(const std::filesystem::path& dir,
                                               const std::function<bool(const std::filesystem::path&)>& is_frame);

}  // namespace cdb
