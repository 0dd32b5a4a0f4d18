#include "exact_number.h"

#include <charconv>
#include <cmath>

namespace cdb {

std::string exact_number(double x) {
  if (std::isnan(x)) return "";
  char text[64];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  return std::string(text, end);
}

}  // namespace cdb
