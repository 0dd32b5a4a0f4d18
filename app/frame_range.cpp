#include "frame_range.h"

#include "core/error.h"

namespace cdb {

namespace {
uint32_t parse_index(const std::string& s, const std::string& whole) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
    fail_usage("--frames '" + whole + "': expected A:B with non-negative integers");
  return uint32_t(std::stoul(s));
}
}  // namespace

FrameRange parse_frame_range(const std::string& text, uint32_t num_frames) {
  FrameRange r{0, num_frames};
  if (text.empty()) return r;
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    r.first = parse_index(text, text);
    r.last = r.first + 1;
  } else {
    r.first = parse_index(text.substr(0, colon), text);
    const std::string b = text.substr(colon + 1);
    r.last = b.empty() ? num_frames : parse_index(b, text);
  }
  if (r.first >= r.last) fail_usage("--frames '" + text + "': empty range");
  if (r.last > num_frames)
    fail_usage("--frames '" + text + "': the scene has only " + std::to_string(num_frames) + " frames");
  return r;
}

}  // namespace cdb
