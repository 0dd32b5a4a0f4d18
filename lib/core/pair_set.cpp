#include "cdbench/core/pair_set.h"

#include <cstddef>
#include <memory>

#include "cdbench/exec/host_exec.h"

namespace cdb {

void sort_by_pair_key(std::vector<PrimPair>& pairs) {
  const size_t n = pairs.size();
  if (n < 2) return;
  HostExec exec;
  // A key holds its whole pair, so the sorted keys are the sorted pairs. The buffers are
  // left uninitialized: every element is written before it is read.
  const auto keys = std::make_unique_for_overwrite<uint64_t[]>(n);
  const auto sorted = std::make_unique_for_overwrite<uint64_t[]>(n);
  const size_t temp_bytes = exec.sort_keys_temp_bytes(n);
  const auto temp = std::make_unique_for_overwrite<std::byte[]>(temp_bytes);
  exec.for_each_n(n, [&](uint32_t i) { keys[i] = pair_key(pairs[i]); });
  exec.sort_keys(keys.get(), sorted.get(), n, 64, temp.get(), temp_bytes);
  exec.for_each_n(n, [&](uint32_t i) { pairs[i] = {uint32_t(sorted[i] >> 32), uint32_t(sorted[i])}; });
}

PairSetDiff diff_pair_sets(const std::vector<PrimPair>& expected,
                           const std::vector<PrimPair>& actual, size_t keep) {
  PairSetDiff d;
  d.expected = expected.size();
  d.actual = actual.size();
  auto add = [keep](std::vector<PrimPair>& list, uint64_t& count, PrimPair p) {
    if (list.size() < keep) list.push_back(p);
    ++count;
  };
  size_t i = 0, j = 0;
  while (i < expected.size() || j < actual.size()) {
    if (j > 0 && j < actual.size() && pair_key(actual[j]) == pair_key(actual[j - 1])) {
      add(d.unexpected, d.unexpected_count, actual[j++]);
      continue;
    }
    if (j == actual.size() || (i < expected.size() && pair_key(expected[i]) < pair_key(actual[j]))) {
      add(d.missing, d.missing_count, expected[i++]);
    } else if (i == expected.size() || pair_key(actual[j]) < pair_key(expected[i])) {
      add(d.unexpected, d.unexpected_count, actual[j++]);
    } else {
      ++i;
      ++j;
    }
  }
  return d;
}

PairAccuracy pair_accuracy(const std::vector<PrimPair>& expected, const std::vector<PrimPair>& actual) {
  const PairSetDiff d = diff_pair_sets(expected, actual, 0);
  PairAccuracy a;
  a.missed = d.missing_count;
  a.false_positives = d.unexpected_count;
  if (!expected.empty()) a.recall = double(expected.size() - d.missing_count) / double(expected.size());
  if (!actual.empty()) a.precision = double(actual.size() - d.unexpected_count) / double(actual.size());
  return a;
}

}  // namespace cdb
