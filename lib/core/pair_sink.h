#pragma once
#include "core/atomics.h"
#include "core/pair.h"

namespace cdb {

// Where a query writes its pairs: a counter and a buffer of fixed capacity. Every pair is
// counted; pairs past the capacity are not stored, and the caller, seeing count >
// capacity after the kernel, grows the buffer (logged, counted) and runs the query again.
// Nothing is ever truncated silently.
struct PairSink {
  PrimPair* out;
  unsigned long long* count;
  unsigned long long capacity;

  CDB_HD_INLINE void emit(uint32_t i, uint32_t j) const {
    const unsigned long long slot = claim_one(count);
    if (slot < capacity) out[slot] = make_pair_ordered(i, j);
  }
};

}  // namespace cdb
