#pragma once
#include <stdexcept>
#include <string>

namespace cdb {

// Every failure a user can cause (bad input, unknown option) or meet (out of memory,
// a CUDA error) is thrown as this, with a message naming what and where.
struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] inline void fail(const std::string& message) { throw Error(message); }

}  // namespace cdb
