#include "library_errors.h"

#include <cerrno>
#include <filesystem>
#include <new>
#include <stdexcept>
#include <string>
#include <system_error>

#include <nlohmann/json.hpp>

#include "cdbench/core/error.h"

namespace cdb {
namespace {

std::string filesystem_text(const std::filesystem::filesystem_error& e) {
  std::string paths;
  if (!e.path1().empty()) paths = e.path1().string();
  if (!e.path2().empty()) paths += (paths.empty() ? "" : " -> ") + e.path2().string();
  return (paths.empty() ? std::string("a file operation failed") : paths) + ": " + path_error_text(e.code());
}

// nlohmann's messages start with "[json.exception.KIND.ID] "; the rest is plain.
std::string json_detail(const nlohmann::json::exception& e) {
  const std::string what = e.what();
  const size_t close = what.find("] ");
  return close == std::string::npos ? what : what.substr(close + 2);
}

}  // namespace

std::string path_error_text(const std::error_code& ec) {
  if (ec.category() != std::generic_category() && ec.category() != std::system_category()) return ec.message();
  switch (ec.value()) {
    case ELOOP: return "its symbolic links form a loop; point the link at a real file or directory";
    case ENAMETOOLONG: return "the name is too long for the file system (most allow 255 bytes a name); choose a shorter one";
    case ENOTDIR: return "a part of the path is a file, not a directory; name a directory there";
    case EISDIR: return "it is a directory; name a file";
    case EACCES:
    case EPERM: return "permission denied; check the permissions of the path";
    case ENOENT: return "no such file or directory";
    case ENOSPC: return "no space left on device";
    default: return ec.message();
  }
}

std::string error_text(const std::exception& e) {
  if (dynamic_cast<const Error*>(&e)) return e.what();
  if (const auto* fs = dynamic_cast<const std::filesystem::filesystem_error*>(&e)) return filesystem_text(*fs);
  if (const auto* j = dynamic_cast<const nlohmann::json::exception*>(&e)) {
    // 316: text that is not UTF-8 written as JSON (results attributes, status files,
    // --json): a name given on the command line or read from a directory.
    if (j->id == 316)
      return "a scene, file or option name is not valid UTF-8 (" + json_detail(*j) +
             "), and results record names as UTF-8 text: rename it with UTF-8 characters";
    return "malformed JSON data: " + json_detail(*j);
  }
  if (dynamic_cast<const std::bad_alloc*>(&e)) return "out of host memory: try a smaller scene or fewer frames";
  // std::stoul and friends name only themselves ("stoul").
  if (dynamic_cast<const std::out_of_range*>(&e)) return std::string("a number is out of range (") + e.what() + ")";
  if (dynamic_cast<const std::invalid_argument*>(&e)) return std::string("a value is not a number (") + e.what() + ")";
  return e.what();
}

}  // namespace cdb
