#pragma once
// How the readers meet their input files: directories of frames in natural name order,
// formats told apart by extension, whole files read at once, little-endian fields.
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

namespace cdb {

// Natural order of file names: runs of digits compare as numbers (leading zeros ignored),
// so frame2.obj comes before frame10.obj; other characters compare by their byte value,
// and names equal that way (f01, f1) fall back to text order, so the order is total.
bool natural_less(std::string_view a, std::string_view b);

// The file's extension in lower case (.OBJ -> .obj): the readers tell formats apart by it.
std::string lower_extension(const std::filesystem::path& file);

// The regular files of `dir` that `is_frame` accepts by name, in natural order. A link
// among them that leads nowhere (dangling, or a loop) is refused naming it, rather than
// leaving a gap in the frames; so is an entry with a frame's name that is not a regular
// file (a FIFO, a device, a directory, or a link to one), and a directory that cannot be
// listed. Frames read through a link are fine.
std::vector<std::filesystem::path> frame_files(const std::filesystem::path& dir,
                                               const std::function<bool(const std::filesystem::path&)>& is_frame);

// The file's bytes; "FILE: cannot open<what>" when it cannot be opened, "FILE: read
// failed" when reading stops short.
std::string read_file(const std::filesystem::path& file, const std::string& what = "");

// An unsigned integer of `bytes` bytes stored little-endian, whatever the host's order.
inline uint64_t little_endian(const char* p, size_t bytes) {
  uint64_t v = 0;
  for (size_t i = 0; i < bytes; ++i) v |= uint64_t(uint8_t(p[i])) << (8 * i);
  return v;
}

}  // namespace cdb
