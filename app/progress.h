#pragma once
// Progress of a run on stderr: a bar with frames/s and ETA on a terminal, redrawn at most
// ten times a second; otherwise (logs, CI) a plain line every ten seconds, or nothing.
#include <chrono>
#include <cstdint>

namespace cdb {

class Progress {
 public:
  enum class Mode { bar, lines, off };
  // A bar when stderr is a terminal; else lines, unless quiet.
  static Mode mode_for(bool quiet);

  Progress(uint32_t total_frames, Mode mode);
  // Another frame finished (`done` frames so far).
  void update(uint32_t done);
  // Takes the bar off the terminal, so a line printed next is not drawn over it.
  void clear();
  // The run ended: clears the bar.
  void finish() { clear(); }

 private:
  void draw(uint32_t done, double seconds);

  uint32_t total_;
  Mode mode_;
  bool shown_ = false;
  uint32_t done_ = 0;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace cdb
