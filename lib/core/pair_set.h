#pragma once
// Set comparison of two sorted pair lists: what verify and the tests check.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cdbench/core/pair.h"

namespace cdb {

struct PairSetDiff {
  uint64_t expected = 0, actual = 0;
  std::vector<PrimPair> missing;     // in expected only (a recall loss), first few kept
  std::vector<PrimPair> unexpected;  // in actual only (or duplicated), first few kept
  uint64_t missing_count = 0, unexpected_count = 0;
  bool equal() const { return missing_count == 0 && unexpected_count == 0; }
};

// Recall (oracle pairs found / oracle pairs) and precision (reported pairs the oracle has /
// reported pairs; a duplicate counts as a false positive) of `actual` against `expected`,
// both sorted by pair_key. Empty sets count as 1.
struct PairAccuracy {
  double recall = 1.0, precision = 1.0;
  uint64_t missed = 0, false_positives = 0;
};
PairAccuracy pair_accuracy(const std::vector<PrimPair>& expected, const std::vector<PrimPair>& actual);

// Sorts pairs by pair_key: a radix sort over the host executor's threads (the pair lists
// every checked frame reads back are long, and std::sort on one thread was the tests' top
// cost).
void sort_by_pair_key(std::vector<PrimPair>& pairs);

// Both inputs sorted by pair_key. Duplicates in `actual` count as unexpected.
PairSetDiff diff_pair_sets(const std::vector<PrimPair>& expected,
                           const std::vector<PrimPair>& actual, size_t keep = 8);

}  // namespace cdb
