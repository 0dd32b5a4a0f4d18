#include "output_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

// The pid the holder wrote into the lock file, "" when it has not written it yet.
std::string holder_pid(int fd) {
  char text[32] = {};
  const ssize_t n = pread(fd, text, sizeof text - 1, 0);
  std::string pid(text, n > 0 ? size_t(n) : 0);
  while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
  return pid.find_first_not_of("0123456789") == std::string::npos ? pid : "";
}

bool same_file(int fd, const std::string& path) {
  struct stat held {}, named {};
  return fstat(fd, &held) == 0 && stat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
         held.st_ino == named.st_ino;
}

}  // namespace

OutputLock::OutputLock(const std::filesystem::path& file) : path_(file.string() + ".lock") {
  for (;;) {
    fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      // The first file made in the directory: its failure is the directory's.
      const int error = errno;
      const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : ".";
      std::error_code ec;
      // /proc and /sys refuse new files with ENOENT, which reads as a missing directory.
      const std::string why = error == ENOENT && std::filesystem::is_directory(dir, ec)
                                  ? "the file system does not take new files here"
                                  : std::strerror(error);
      fail("--out " + file.string() + ": cannot write in directory " + dir.string() + ": " + why);
    }
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      const std::string pid = error == EWOULDBLOCK ? holder_pid(fd_) : "";
      close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK)
        fail_usage(file.string() + " is being written by another cdbench run" + (pid.empty() ? "" : " (pid " + pid + ")") +
                   "; wait for it to end or give another --out");
      fail("--out " + file.string() + ": cannot lock " + path_ + ": " + std::strerror(error));
    }
    // The run that held the lock removes the file before releasing it: a lock taken on a
    // file no longer under that name guards nothing, so take it again on the current one.
    if (same_file(fd_, path_)) break;
    close(fd_);
  }
  // Unwritten, only a second run's message loses the pid; the lock holds regardless.
  const std::string pid = std::to_string(getpid()) + "\n";
  const bool written = ftruncate(fd_, 0) == 0 && pwrite(fd_, pid.data(), pid.size(), 0) == ssize_t(pid.size());
  (void)written;
}

OutputLock::OutputLock(OutputLock&& other) noexcept
    : path_(std::move(other.path_)), fd_(std::exchange(other.fd_, -1)) {}

OutputLock::~OutputLock() {
  if (fd_ < 0) return;
  unlink(path_.c_str());
  close(fd_);
}

}  // namespace cdb
