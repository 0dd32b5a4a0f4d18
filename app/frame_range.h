#pragma once
#include <cstdint>
#include <string>

namespace cdb {

// A half-open frame range [first, last) parsed from "A:B", "A:" or "A".
struct FrameRange {
  uint32_t first = 0, last = 0;
};

FrameRange parse_frame_range(const std::string& text, uint32_t num_frames);

}  // namespace cdb
