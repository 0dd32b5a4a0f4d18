#include "progress.h"

#include <unistd.h>

#include <cstdio>
#include <string>

namespace cdb {
namespace {

using Clock = std::chrono::steady_clock;
constexpr auto kBarInterval = std::chrono::milliseconds(100);
constexpr auto kLineInterval = std::chrono::seconds(10);
constexpr int kBarWidth = 30;

std::string duration_text(double seconds) {
  const long s = long(seconds + 0.5);
  char text[32];
  if (s >= 3600)
    std::snprintf(text, sizeof text, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  else
    std::snprintf(text, sizeof text, "%ld:%02ld", s / 60, s % 60);
  return text;
}

}  // namespace

Progress::Mode Progress::mode_for(bool quiet) {
  if (isatty(STDERR_FILENO)) return Mode::bar;
  return quiet ? Mode::off : Mode::lines;
}

Progress::Progress(uint32_t total_frames, Mode mode)
    : total_(total_frames), mode_(mode), start_(Clock::now()), last_(start_) {}

void Progress::update(uint32_t done) {
  done_ = done;
  if (mode_ == Mode::off) return;
  const auto now = Clock::now();
  const bool last_frame = done == total_;
  if (mode_ == Mode::bar && (!shown_ || now - last_ >= kBarInterval || last_frame)) {
    draw(done, std::chrono::duration<double>(now - start_).count());
    last_ = now;
  } else if (mode_ == Mode::lines && now - last_ >= kLineInterval && !last_frame) {
    draw(done, std::chrono::duration<double>(now - start_).count());
    last_ = now;
  }
}

void Progress::draw(uint32_t done, double seconds) {
  const double rate = seconds > 0 ? done / seconds : 0;
  const std::string eta = rate > 0 ? duration_text((total_ - done) / rate) : "?";
  if (mode_ == Mode::lines) {
    std::fprintf(stderr, "progress: %u/%u frames, %.1f frames/s, ETA %s\n", done, total_, rate, eta.c_str());
    return;
  }
  const int filled = total_ ? int(double(kBarWidth) * done / total_) : kBarWidth;
  std::string bar(size_t(filled), '#');
  bar.resize(kBarWidth, '.');
  std::fprintf(stderr, "\r\033[K[%s] %u/%u frames  %.1f frames/s  ETA %s", bar.c_str(), done, total_, rate,
               eta.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void Progress::clear() {
  if (!shown_) return;
  std::fflush(stdout);
  std::fprintf(stderr, "\r\033[K");
  std::fflush(stderr);
  shown_ = false;
}

}  // namespace cdb
