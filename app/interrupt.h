#pragma once
// SIGINT and SIGTERM during a run. The handler only records which signal came; the run
// checks between frames and stops cleanly, so a results file is closed (as incomplete),
// not cut off. A second signal gets the default action: a stuck run can still be killed.
#include <signal.h>

namespace cdb {

class InterruptScope {
 public:
  InterruptScope();   // installs the handlers
  ~InterruptScope();  // restores the ones there before
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;
  // The signal that arrived since construction, 0 when none.
  int signal() const;

 private:
  struct sigaction previous_int_ {}, previous_term_ {};
};

const char* signal_name(int signal);

}  // namespace cdb
