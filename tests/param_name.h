#pragma once
// A parameterized test's name from free text (a case name, a file's stem): gtest takes
// letters, digits and '_' only, so every other character becomes '_'.
#include <cctype>
#include <string>

namespace cdb {

inline std::string param_name(std::string text) {
  for (char& ch : text)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return text;
}

}  // namespace cdb
