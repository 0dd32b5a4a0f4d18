#pragma once
// Numbers for machines (report --csv, compare --csv): the shortest text that reads back as
// the same double, so nothing is rounded away and no digit is made up.
#include <string>

namespace cdb {

// "" for NaN (no value), "inf" and "-inf" for the infinities.
std::string exact_number(double x);

}  // namespace cdb
