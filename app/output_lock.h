#pragma once
// One writer per results file. Two runs writing one --out at once would each truncate the
// other's file, and the one that finished would call the wreck its results. A run holds an
// exclusive lock on FILE.lock beside its file (flock, released by the system however the
// process ends) from before its scene loads until it exits; a second run is refused at
// once, naming the first one's pid.
#include <filesystem>
#include <string>

namespace cdb {

class OutputLock {
 public:
  // Takes the lock for `file` (its directory must exist). Throws UsageError "FILE is being
  // written by another cdbench run (pid N)" when another process holds it, Error when the
  // lock file cannot be made.
  explicit OutputLock(const std::filesystem::path& file);
  // Removes the lock file, then releases the lock. A process killed before this leaves the
  // file behind: harmless, the next run takes the lock on it and removes it.
  ~OutputLock();
  OutputLock(OutputLock&& other) noexcept;
  OutputLock& operator=(OutputLock&&) = delete;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

 private:
  std::string path_;  // FILE.lock
  int fd_ = -1;
};

}  // namespace cdb
