#pragma once
// What a call throws as cdb::Error, for tests that check an error's wording.
#include <functional>
#include <string>

#include "cdbench/core/error.h"

namespace cdb::test {

// The message of the cdb::Error `f` throws, or "no error".
inline std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace cdb::test
