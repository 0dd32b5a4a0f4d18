#include "scenes/load/replace_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

namespace cdb {

std::string replace_file(const std::filesystem::path& file, const std::function<void(std::ostream&)>& write) {
  // The process id keeps two processes that fill one cache from writing one temporary.
  const std::filesystem::path part = file.string() + ".part." + std::to_string(::getpid());
  std::error_code ignored;
  errno = 0;
  {
    std::ofstream os(part, std::ios::binary | std::ios::trunc);
    if (os) write(os);
    os.close();
    if (!os) {
      const int error = errno;
      std::filesystem::remove(part, ignored);
      return file.string() + ": write failed" + (error ? std::string(": ") + std::strerror(error) : "");
    }
  }
  std::error_code ec;
  std::filesystem::rename(part, file, ec);
  if (ec) {
    std::filesystem::remove(part, ignored);
    return file.string() + ": cannot move the written file into place: " + ec.message();
  }
  return {};
}

}  // namespace cdb
