#include "interrupt.h"

#include <csignal>

namespace cdb {
namespace {

// The one global: a signal handler can only talk to the program through one.
volatile std::sig_atomic_t arrived = 0;

void record(int signal) { arrived = signal; }

}  // namespace

InterruptScope::InterruptScope() {
  arrived = 0;
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
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
}

int InterruptScope::signal() const { return arrived; }

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "a signal";
  }
}

}  // namespace cdb
