#include "damaged_file_guard.h"

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

void on_alarm(int) { write_and_exit(timed_out); }
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
                         " s: the file is damaged (its HDF5 structure loops); leave it out or write it again\n");
  compose(crashed, prefix + "the HDF5 library crashed reading it: the file is damaged; leave it out or write it again\n");
  std::signal(SIGALRM, on_alarm);
  std::signal(SIGSEGV, on_crash);
  std::signal(SIGBUS, on_crash);
  alarm(seconds);
}

DamagedFileGuard::~DamagedFileGuard() {
  alarm(0);
  std::signal(SIGALRM, SIG_DFL);
  std::signal(SIGSEGV, SIG_DFL);
  std::signal(SIGBUS, SIG_DFL);
}

}  // namespace cdb
