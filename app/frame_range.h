#pragma once
#include <cstdint>
#include <string>

namespace cdb {

// A half-open frame range [first, last) parsed from "A:B", "A:" or "A".
struct FrameRange {
  uint32_t first = 0, last = 0;
};

FrameRange parse_frame_range(const std::string& text, uint32_t num_frames);

// The warning a run prints when `range` holds no frame after the first `warmup` (`text`:
// --frames as given), else "": the summary then takes the warm-up frames in, which it must
// not do silently.
std::string warmup_warning(const FrameRange& range, uint32_t warmup, const std::string& text);

}  // namespace cdb
