#include "damaged_file_guard.h"

#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstring>

#include "exit_codes.h"

namespace cdb {
namespace {

// The globals: a signal handler reaches the program only through them. Its text is
// composed before the read, since a handler may only write and exit.
char timed_out[1024];
char crashed[1024];

void write_and_exit(const char* text) {
  const ssize_t ignored = write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
  _exit(kExitFailure);
}

void on_timer(int) { write_and_exit(timed_out); }

// The read's budget counts this process's CPU time (ITIMER_PROF, SIGPROF), not the clock's:
// a reader stopped (Ctrl-Z, SIGSTOP) or starved by other work is not a damaged file, and the
// loops HDF5 falls into spin.
void set_timer(unsigned seconds) {
  itimerval budget {};
  budget.it_value.tv_sec = seconds;
  setitimer(ITIMER_PROF, &budget, nullptr);
}
void on_crash(int) { write_and_exit(crashed); }

void compose(char (&out)[1024], const std::string& text) {
  const size_t n = std::min(text.size(), sizeof out - 1);
  std::memcpy(out, text.data(), n);
  out[n] = '\0';
}

}  // namespace

DamagedFileGuard::DamagedFileGuard(const std::string& who, const std::string& file, unsigned seconds) {
  const std::string prefix = "cdbench: " + who + ": " + file.substr(0, 600) + ": ";
  compose(timed_out, prefix + "reading it did not finish within " + std::to_string(seconds) +
                         " s of CPU time: the file is damaged (its HDF5 structure loops); leave it out or write it again\n");
  compose(crashed, prefix + "the HDF5 library crashed reading it: the file is damaged; leave it out or write it again\n");
  std::signal(SIGPROF, on_timer);
  std::signal(SIGSEGV, on_crash);
  std::signal(SIGBUS, on_crash);
  set_timer(seconds);
}

DamagedFileGuard::~DamagedFileGuard() {
  set_timer(0);
  std::signal(SIGPROF, SIG_DFL);
  std::signal(SIGSEGV, SIG_DFL);
  std::signal(SIGBUS, SIG_DFL);
}

}  // namespace cdb
