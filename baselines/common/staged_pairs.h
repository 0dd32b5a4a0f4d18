#pragma once
// What every baseline pair kernel shares: the sink its pairs go to, staged per block in
// shared memory where the executor stages them (Exec::for_each_staged,
// core/append_stage.h). A kernel derives from this, so it is filled {{sink}, ...}, and
// writes through sink.staged(stage).
#include "cdbench/core/pair_sink.h"

namespace cdb {

struct StagedPairs {
  PairSink sink;
  using Stage = PairStage;
#if defined(__CUDACC__)
  __device__ void flush(Stage& s) const { sink.flush(s); }
#endif
};

}  // namespace cdb
