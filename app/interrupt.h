#pragma once
// The signals that ask a program to stop (SIGINT, SIGTERM, SIGHUP when the terminal goes,
// SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGXCPU at a CPU time limit) during a run. The
// handler only records which signal came; the run checks between frames and stops
// cleanly, so a results file is closed (as incomplete) with the frames done, not cut off.
// A second signal gets the default action: a stuck run can still be killed.
//
// Before there is anything to close cleanly (a run loading its scene), a scope made with
// Mode::exit_at_once ends the program at once, with a line on stderr and 128 + the
// signal; defer() switches it to recording, before the results file is created, so no
// signal can leave a file cut off between its creation and the first frame.
#include <signal.h>

namespace cdb {

class InterruptScope {
 public:
  enum class Mode { record, exit_at_once };
  // Installs the handlers.
  explicit InterruptScope(Mode mode = Mode::record);
  ~InterruptScope();  // restores the ones there before
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  // From now on signals are recorded, not acted on (Mode::record).
  void defer();
  // The signal that arrived since construction, 0 when none.
  int signal() const;

 private:
  struct sigaction previous_[8] {};  // one per signal handled, in interrupt.cpp's order
};

const char* signal_name(int signal);

// The signals a scope handles, for code that holds them back for a moment.
sigset_t stop_signal_set();

}  // namespace cdb
