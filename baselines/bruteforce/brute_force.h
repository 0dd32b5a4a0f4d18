#pragma once
// The exact oracle: every pair of triangle boxes tested, O(N^2), on either executor.
#include <cstdint>

#include "core/aabb.h"
#include "core/pair_sink.h"
#include "exec/balance.h"

namespace cdb {

struct BruteForceFn {
  uint32_t n;
  const vec4f* lo;
  const vec4f* hi;
  PairSink sink;
  using Stage = PairStage;
  CDB_HD void operator()(uint32_t i, Stage* stage = nullptr) const {
    const PairSink out = stage ? sink.staged(stage) : sink;
    const vec4f alo = lo[i], ahi = hi[i];
    for (uint32_t j = i + 1; j < n; ++j)
      if (overlaps(alo, ahi, lo[j], hi[j])) out.emit(i, j);
  }
#if defined(__CUDACC__)
  __device__ void flush(Stage& s) const { sink.flush(s); }
#endif
};

template <class Exec>
void brute_force_pairs(Exec& exec, uint32_t n, const vec4f* lo, const vec4f* hi,
                       const PairSink& sink) {
  exec.for_each_staged(n, BruteForceFn{n, lo, hi, sink}, Balance::uneven);
}

}  // namespace cdb
