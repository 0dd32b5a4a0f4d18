#pragma once
#include <stdexcept>
#include <string>

namespace cdb {

// Every failure a user can cause (bad input, unknown option) or meet (out of memory,
// a CUDA error) is thrown as this, with a message naming what and where.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A command line that cannot be accepted: an unknown name or a malformed or conflicting
// option value, found before any work starts (the CLI exits 2 on it, 1 on other errors).
struct UsageError : Error {
  using Error::Error;
};

[[noreturn]] inline void fail(const std::string& message) { throw Error(message); }
[[noreturn]] inline void fail_usage(const std::string& message) { throw UsageError(message); }

}  // namespace cdb
