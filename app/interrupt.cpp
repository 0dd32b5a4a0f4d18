#include "interrupt.h"
#include "exit_codes.h"

#include <unistd.h>

#include <csignal>
#include <cstddef>
#include <iterator>
#include <cstring>

namespace cdb {
namespace {

// The globals: a signal handler can only talk to the program through them. `arrived` is
// the signal that came; `exit_at_once` says whether the handler ends the program itself.
volatile std::sig_atomic_t arrived = 0;
volatile std::sig_atomic_t exit_at_once = 0;

// Every signal handled (signal_name names each); previous_ in the header has a slot each.
constexpr int kStopSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGXCPU};

void write_text(const char* text) {
  const ssize_t ignored = write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

void record(int signal) {
  arrived = signal;
  if (!exit_at_once) return;
  // Only async-signal-safe calls here: write and _exit, with text fixed in advance.
  write_text("cdbench: interrupted by ");
  write_text(signal_name(signal));
  write_text(" before the run started\n");
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
  static_assert(std::size(kStopSignals) == std::size(decltype(previous_){}));
  for (size_t k = 0; k < std::size(kStopSignals); ++k) sigaction(kStopSignals[k], &action, &previous_[k]);
}

InterruptScope::~InterruptScope() {
  exit_at_once = 0;
  for (size_t k = 0; k < std::size(kStopSignals); ++k) sigaction(kStopSignals[k], &previous_[k], nullptr);
}

void InterruptScope::defer() { exit_at_once = 0; }

int InterruptScope::signal() const { return arrived; }

sigset_t stop_signal_set() {
  sigset_t set;
  sigemptyset(&set);
  for (const int signal : kStopSignals) sigaddset(&set, signal);
  return set;
}

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGQUIT: return "SIGQUIT";
    case SIGUSR1: return "SIGUSR1";
    case SIGUSR2: return "SIGUSR2";
    case SIGALRM: return "SIGALRM";
    case SIGXCPU: return "SIGXCPU";
    default: return "a signal";
  }
}

}  // namespace cdb
