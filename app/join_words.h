#pragma once
// Words joined by a separator ("a, b, c"), for messages and tables.
#include <string>
#include <vector>

namespace cdb {

inline std::string join_words(const std::vector<std::string>& words, const char* sep) {
  std::string s;
  for (const std::string& w : words) s += (s.empty() ? "" : sep) + w;
  return s;
}

}  // namespace cdb
