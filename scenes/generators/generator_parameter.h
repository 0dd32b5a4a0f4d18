#pragma once
// What `scenes info` and `--set` errors say about a generator parameter.
#include <string>

namespace cdb {

struct GeneratorParameter {
  std::string key;
  std::string kind;      // number, integer or text
  std::string fallback;  // the default
  std::string range;     // "lo..hi" for integers, else empty
  std::string value;     // what this scene uses
};

}  // namespace cdb
