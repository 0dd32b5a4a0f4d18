#include "output_path.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/error.h"

namespace cdb {

void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path file(path);
  if (path.empty()) fail_usage("--out: empty file name");
  if (!file.has_filename() || fs::is_directory(file))
    fail_usage("--out " + path + ": names a directory; give a file, e.g. " + (file / "run.h5").lexically_normal().string());
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) fail("--out " + path + ": cannot create directory " + dir.string() + ": " + ec.message());
  if (!fs::is_directory(dir)) fail("--out " + path + ": " + dir.string() + " is not a directory");
  // Opening the file is the only test that also holds for root and for read-only mounts;
  // appending leaves an existing file as it is, and a file made here is removed again.
  const bool existed = fs::exists(file);
  if (!std::ofstream(file, std::ios::app))
    fail("--out " + path + ": cannot write " + (existed ? "this file" : "in directory " + dir.string()) + ": " +
         std::strerror(errno));
  if (!existed) fs::remove(file, ec);
}

}  // namespace cdb
