#pragma once
// Checks of numeric options whose messages say what is expected: CLI11's own
// (NonNegativeNumber, PositiveNumber) print their bound as a 309-digit double and called 0
// outside a range starting at 0 (`--repeat 0`), and let inf and nan through.
#include <CLI/CLI.hpp>

#include <cstdint>

namespace cdb {

// A finite number >= lo (inf, nan and words refused).
CLI::Validator finite_at_least(double lo);

// A whole number in [lo, hi], checked as text before it is read into a narrower type.
CLI::Validator whole_in(uint64_t lo, uint64_t hi);

}  // namespace cdb
