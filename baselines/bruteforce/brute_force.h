#pragma once
// The exact oracle: every pair of triangle boxes tested, O(N^2), on either executor.
#include <cstdint>

#include "cdbench/core/aabb.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/balance.h"

namespace cdb {

struct BruteForceFn {
  uint32_t n;
  const vec4f* lo;
  const vec4f* hi;
  PairSink sink;
  CDB_HD void operator()(uint32_t i) const {
    const vec4f alo = lo[i], ahi = hi[i];
    for (uint32_t j = i + 1; j < n; ++j)
      if (overlaps(alo, ahi, lo[j], hi[j])) sink.emit(i, j);
  }
};

template <class Exec>
void brute_force_pairs(Exec& exec, uint32_t n, const vec4f* lo, const vec4f* hi,
                       const PairSink& sink) {
  exec.for_each_n(n, BruteForceFn{n, lo, hi, sink}, Balance::uneven);
}

}  // namespace cdb
