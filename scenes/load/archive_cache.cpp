#include "scenes/load/archive_cache.h"

#include <zlib.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <vector>

#include "cdbench/core/error.h"
#include "scenes/load/replace_file.h"

namespace cdb {
namespace {

constexpr size_t kBlock = 512;  // tar's record unit

uint64_t octal(const char* field, size_t width) {
  uint64_t v = 0;
  for (size_t i = 0; i < width && field[i]; ++i)
    if (field[i] >= '0' && field[i] <= '7') v = v * 8 + uint64_t(field[i] - '0');
  return v;
}

// A string field of a tar header: up to `width` characters, NUL-terminated when shorter.
std::string field(const char* f, size_t width) { return std::string(f, strnlen(f, width)); }

struct GzFile {
  gzFile f;
  explicit GzFile(const std::filesystem::path& p) : f(gzopen(p.c_str(), "rb")) {}
  ~GzFile() {
    if (f) gzclose(f);
  }
  // Reads exactly n bytes; false at a clean end, fails on a short or damaged read.
  bool read(char* out, size_t n, const std::string& archive) {
    size_t got = 0;
    while (got < n) {
      const int r = gzread(f, out + got, unsigned(std::min<size_t>(n - got, 1u << 30)));
      if (r < 0) {
        int code;
        fail(archive + ": damaged archive: " + gzerror(f, &code));
      }
      if (r == 0) break;
      got += size_t(r);
    }
    if (got != 0 && got != n) fail(archive + ": archive cut short");
    return got == n;
  }
};

}  // namespace

std::filesystem::path scene_cache_dir() {
  if (const char* env = std::getenv("CDBENCH_CACHE"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "cdbench";
  if (const char* home = std::getenv("HOME"); home && *home)
    return std::filesystem::path(home) / ".cache" / "cdbench";
  fail("no scene cache directory: set CDBENCH_CACHE (or XDG_CACHE_HOME or HOME)");
}

std::filesystem::path extract_from_archive(const std::filesystem::path& archive, const std::string& member) {
  const std::string name = archive.string();
  if (!std::filesystem::is_regular_file(archive)) fail(name + ": no such file");
  if (member.empty() || member.front() == '/' || member.find("..") != std::string::npos)
    fail(name + ": member '" + member + "': must be a relative path inside the archive");
  // One directory per archive version: its path, size and modification time.
  std::string key = std::filesystem::absolute(archive).string();
  std::replace(key.begin(), key.end(), '/', '_');
  key += "-" + std::to_string(std::filesystem::file_size(archive)) + "-" +
         std::to_string(std::filesystem::last_write_time(archive).time_since_epoch().count());
  const std::filesystem::path out = scene_cache_dir() / "extracted" / key / member;
  if (std::filesystem::is_regular_file(out)) return out;

  GzFile gz(archive);
  if (!gz.f) fail(name + ": cannot open archive");
  char header[kBlock];
  std::string long_name;
  std::vector<char> data;
  while (gz.read(header, kBlock, name)) {
    if (header[0] == 0) break;  // the end-of-archive blocks
    const uint64_t size = octal(header + 124, 12);
    const char type = header[156];
    std::string path = long_name.empty() ? field(header, 100) : long_name;
    if (long_name.empty() && std::memcmp(header + 257, "ustar", 5) == 0 && header[345])
      path = field(header + 345, 155) + "/" + path;
    long_name.clear();
    data.resize(size_t((size + kBlock - 1) / kBlock * kBlock));
    if (!data.empty() && !gz.read(data.data(), data.size(), name)) fail(name + ": archive cut short");
    if (type == 'L') {  // GNU long name: the next header's path
      long_name = std::string(data.data(), strnlen(data.data(), size_t(size)));
      continue;
    }
    if (path.rfind("./", 0) == 0) path = path.substr(2);
    if (path != member || (type != '0' && type != 0)) continue;
    std::filesystem::create_directories(out.parent_path());
    // Written whole and renamed into place, so a cut-off extraction is never read.
    const std::string failed =
        replace_file(out, [&](std::ostream& f) { f.write(data.data(), std::streamsize(size)); });
    if (!failed.empty()) fail(failed + " (extracting " + member + " from " + name + ")");
    return out;
  }
  fail(name + ": no member '" + member + "' in this archive");
}

}  // namespace cdb
