#pragma once
// Natural order of file names: runs of digits compare as numbers, so frame2.obj comes
// before frame10.obj (plain text order puts f10 and f11 before f2).
#include <string_view>

namespace cdb {

// Digit runs compare by value (leading zeros ignored), other characters by their byte
// value; names equal that way (f01, f1) fall back to text order, so the order is total.
bool natural_less(std::string_view a, std::string_view b);

}  // namespace cdb
