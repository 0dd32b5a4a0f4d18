#pragma once
// HDF5 1.10 follows some damaged files into an endless loop (a zeroed global heap, where
// variable-length strings live, spins in H5HG_read) or a crash, before it can return an
// error (tests/test_input_mutations.cpp found both). While a guard lives, such a read ends
// the program with exit 1 and a line naming the file, instead of hanging or dumping core.
#include <string>

namespace cdb {

class DamagedFileGuard {
 public:
  // `who`: the command ("report", "compare", "sweep"); `seconds`: the CPU time reading one file may take.
  DamagedFileGuard(const std::string& who, const std::string& file, unsigned seconds = 10);
  ~DamagedFileGuard();
  DamagedFileGuard(const DamagedFileGuard&) = delete;
  DamagedFileGuard& operator=(const DamagedFileGuard&) = delete;
};

}  // namespace cdb
