#include "number_checks.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>

namespace cdb {

CLI::Validator finite_at_least(double lo) {
  char bound[32];
  std::snprintf(bound, sizeof bound, "%g", lo);
  const std::string expected = std::string("a finite number >= ") + bound;
  return CLI::Validator(
      [lo, expected](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v) || v < lo)
          return "expected " + expected + ", not '" + text + "'";
        return "";
      },
      std::string(">= ") + bound);
}

CLI::Validator whole_in(uint64_t lo, uint64_t hi) {
  const std::string expected = "a whole number from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, expected](std::string& text) -> std::string {
        uint64_t v = 0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (text.empty() || ec != std::errc() || end != text.data() + text.size() || v < lo || v > hi)
          return "expected " + expected + ", not '" + text + "'";
        return "";
      },
      std::to_string(lo) + ".." + std::to_string(hi));
}

}  // namespace cdb
