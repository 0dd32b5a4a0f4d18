#include "frame_range.h"

#include <charconv>

#include "cdbench/core/error.h"

namespace cdb {

namespace {
uint32_t parse_index(const std::string& s, const std::string& whole) {
  if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
    fail_usage("--frames '" + whole + "': expected A:B with non-negative integers");
  uint32_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size())
    fail_usage("--frames '" + whole + "': " + s + " is beyond the largest frame index, " + std::to_string(UINT32_MAX));
  return v;
}
}  // namespace

FrameRange parse_frame_range(const std::string& text, uint32_t num_frames) {
  FrameRange r{0, num_frames};
  if (text.empty()) return r;
  const auto colon = text.find(':');
  if (colon == std::string::npos) {
    r.first = parse_index(text, text);
    if (r.first == UINT32_MAX) fail_usage("--frames '" + text + "': the scene has only " + std::to_string(num_frames) + " frames");
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

std::string warmup_warning(const FrameRange& range, uint32_t warmup, const std::string& text) {
  const uint32_t frames = range.last - range.first;
  if (frames > warmup || frames == 0) return "";
  return "--frames " + (text.empty() ? std::string("(all)") : "'" + text + "'") + " gives " + std::to_string(frames) +
         (frames == 1 ? " frame" : " frames") + ", none after --warmup " + std::to_string(warmup) +
         ": the summary takes in the first frame (the build); give more frames to leave it out, or --warmup " +
         std::to_string(frames - 1) + " to say so";
}

}  // namespace cdb
