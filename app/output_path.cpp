#include "output_path.h"

#include <signal.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <system_error>
#include <utility>

#include "cdbench/core/error.h"
#include "interrupt.h"

namespace cdb {

namespace {

// A name that is a directory is a usage error (`example` the file name the message
// suggests); the file's directory is created. Returns it.
std::filesystem::path make_output_dir(const std::string& path, const std::string& example) {
  namespace fs = std::filesystem;
  const fs::path file(path);
  if (path.empty()) fail_usage("--out: empty file name");
  if (!file.has_filename() || fs::is_directory(file))
    fail_usage("--out " + path + ": names a directory; give a file, e.g. " + (file / example).lexically_normal().string());
  std::error_code ec;
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  fs::create_directories(dir, ec);
  if (ec) fail("--out " + path + ": cannot create directory " + dir.string() + ": " + ec.message());
  if (!fs::is_directory(dir)) fail("--out " + path + ": " + dir.string() + " is not a directory");
  return dir;
}

// Opening the file is the only test that also holds for root and for read-only mounts;
// appending leaves an existing file as it is, and a file made here is removed again,
// with the stop signals held back meanwhile so a signal cannot leave it behind empty.
void check_writable(const std::string& path, const std::filesystem::path& dir, bool existed) {
  namespace fs = std::filesystem;
  const fs::path file(path);
  std::error_code ec;
  const sigset_t stop = stop_signal_set();
  sigset_t previous;
  sigprocmask(SIG_BLOCK, &stop, &previous);
  const bool writable = bool(std::ofstream(file, std::ios::app));
  const int error = errno;
  if (writable && !existed) fs::remove(file, ec);
  sigprocmask(SIG_SETMASK, &previous, nullptr);
  if (!writable) {
    // /proc and /sys refuse new files with ENOENT, which reads as a missing directory.
    const std::string why = error == ENOENT && fs::is_directory(dir) ? "the file system does not take new files here"
                                                                      : std::strerror(error);
    fail("--out " + path + ": cannot write " + (existed ? "this file" : "in directory " + dir.string()) + ": " + why);
  }
}

}  // namespace

OutputClaim check_output_path(const std::string& path, bool overwrite) {
  namespace fs = std::filesystem;
  const fs::path file(path);
  const fs::path dir = make_output_dir(path, "run.h5");
  // Before the file is looked at: another run writing it is named as such, not as a file
  // that exists, and nothing here touches a file another run holds.
  OutputLock lock(file);
  std::error_code ec;
  const bool existed = fs::exists(file, ec) || fs::is_symlink(file, ec);
  // A device or pipe (/dev/null) would take the whole run and then fail at the rename or
  // the reopen: a results file is a regular file.
  if (existed && fs::exists(file, ec) && !fs::is_regular_file(file, ec))
    fail_usage("--out " + path + ": not a regular file; results are an HDF5 file, give a file name");
  if (existed && !overwrite)
    fail_usage("--out " + path + ": the file exists; pass --overwrite to replace it (it is replaced only once " +
               "the new run completes)");
  check_writable(path, dir, existed);
  return {existed, std::move(lock)};
}

void check_replaced_output(const std::string& path, const std::string& example) {
  const std::filesystem::path dir = make_output_dir(path, example);
  std::error_code ec;
  check_writable(path, dir, std::filesystem::exists(path, ec));
}

}  // namespace cdb
