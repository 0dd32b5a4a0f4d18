#include "scenes/load/input_files.h"

#include <algorithm>
#include <fstream>
#include <iterator>
#include <system_error>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// What a directory entry that is not a regular file is, for messages.
std::string file_kind(std::filesystem::file_type type) {
  switch (type) {
    case std::filesystem::file_type::directory: return "a directory";
    case std::filesystem::file_type::fifo: return "a FIFO (named pipe)";
    case std::filesystem::file_type::character: return "a character device";
    case std::filesystem::file_type::block: return "a block device";
    case std::filesystem::file_type::socket: return "a socket";
    default: return "neither a file nor a directory";
  }
}

}  // namespace

bool natural_less(std::string_view a, std::string_view b) {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (is_digit(a[i]) && is_digit(b[j])) {
      size_t ei = i, ej = j;
      while (ei < a.size() && is_digit(a[ei])) ++ei;
      while (ej < b.size() && is_digit(b[ej])) ++ej;
      // Compare values without converting (the runs may exceed any integer type).
      size_t si = i, sj = j;
      while (si + 1 < ei && a[si] == '0') ++si;
      while (sj + 1 < ej && b[sj] == '0') ++sj;
      const std::string_view x = a.substr(si, ei - si), y = b.substr(sj, ej - sj);
      if (x.size() != y.size()) return x.size() < y.size();
      if (x != y) return x < y;
      i = ei;
      j = ej;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  if (i < a.size() || j < b.size()) return j < b.size();  // a prefix comes first
  return a < b;
}

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

std::vector<std::filesystem::path> frame_files(const std::filesystem::path& dir,
                                               const std::function<bool(const std::filesystem::path&)>& is_frame) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto status = fs::status(dir, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) fail(dir.string() + ": " + ec.message());
  if (!fs::is_directory(status)) fail(dir.string() + ": not a directory");
  std::vector<fs::path> files;
  fs::directory_iterator it(dir, ec);
  for (; !ec && it != fs::directory_iterator(); it.increment(ec)) {
    const fs::path& p = it->path();
    if (!is_frame(p)) continue;
    std::error_code sec;
    const auto target = fs::status(p, sec);
    if (sec || !fs::exists(target)) {
      std::error_code lec;
      const fs::path to = fs::read_symlink(p, lec);
      const std::string reason = sec && sec != std::errc::no_such_file_or_directory
                                     ? sec.message()
                                     : "it leads to " + (lec ? std::string("nothing") : to.string()) + ", which does not exist";
      fail(p.string() + ": this frame is a link that leads nowhere (" + reason +
           "); restore the file it points to, or remove the link");
    }
    // Skipped, a FIFO, a device or a directory with a frame's name would renumber every
    // later frame without a word; read, a device such as /dev/zero never ends.
    if (!fs::is_regular_file(target))
      fail(p.string() + ": this frame is " + file_kind(target.type()) +
           ", not a regular file; frames are files: remove it or rename it to another extension");
    files.push_back(p);
  }
  if (ec) fail(dir.string() + ": cannot list the directory: " + ec.message());
  std::sort(files.begin(), files.end(), [](const fs::path& a, const fs::path& b) {
    return natural_less(a.filename().native(), b.filename().native());
  });
  return files;
}

std::string read_file(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in) fail(file.string() + ": cannot open" + what);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) fail(file.string() + ": read failed");
  return bytes;
}

}  // namespace cdb
