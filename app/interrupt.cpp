#include "interrupt.h"
#include "exit_codes.h"

#include <unistd.h>

#include <csignal>
#include <cstring>

namespace cdb {
namespace {

// The globals: a signal handler can only talk to the program through them. `arrived` is
// the signal that came; `exit_at_once` says whether the handler ends the program itself.
volatile std::sig_atomic_t arrived = 0;
volatile std::sig_atomic_t exit_at_once = 0;

void record(int signal) {
  arrived = signal;
  if (!exit_at_once) return;
  // Only async-signal-safe calls here: write and _exit, with text fixed in advance.
  const char* line = signal == SIGINT    ? "cdbench: interrupted by SIGINT before the run started\n"
                     : signal == SIGTERM ? "cdbench: interrupted by SIGTERM before the run started\n"
                                         : "cdbench: interrupted before the run started\n";
  const ssize_t ignored = write(STDERR_FILENO, line, std::strlen(line));
  (void)ignored;
  _exit(exit_for_signal(signal));
}

}  // namespace

InterruptScope::InterruptScope(Mode mode) {
  arrived = 0;
  exit_at_once = mode == Mode::exit_at_once;
  struct sigaction action {};
  action.sa_handler = record;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: file reads and writes in flight go on rather than fail with EINTR; the
  // run stops at the next frame boundary anyway.
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &action, &previous_int_);
  sigaction(SIGTERM, &action, &previous_term_);
}

InterruptScope::~InterruptScope() {
  exit_at_once = 0;
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
}

void InterruptScope::defer() { exit_at_once = 0; }

int InterruptScope::signal() const { return arrived; }

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
  }
}

}  // namespace cdb
