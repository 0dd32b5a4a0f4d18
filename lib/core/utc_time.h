#pragma once
#include <string>

namespace cdb {

// The current time in UTC as ISO 8601 to the second, e.g. 2025-01-31T12:00:00Z: what
// results files and sweep logs stamp their events with.
std::string utc_now();

}  // namespace cdb
