#pragma once
// The front pipelines' counter block: what a frame's kernels add to and the host reads back
// once a frame, in one copy (PairBuffer): the pairs first, since every pair sink counts
// there, then per front query and for the inspection. Kernels get pointers into the block
// on the device (PairBuffer::device), the host reads the block itself.
#include <cstddef>
#include <cstdint>

#include "cdbench/front/front.h"
#include "cdbench/front/quality.h"
#include "cdbench/pipeline/plan_step.h"

namespace cdb {

// One front query's counts (pipeline/front_query.h).
struct FrontQueryCounters {
  // Front nodes the frame's operation produced, per kind (FrontKind); may exceed the
  // capacity: the caller grows and runs the operation again.
  unsigned long long produced[2];
  // A probing preserve's count of what an update of its front yields at most, per kind
  // (PreserveFrontFn: its descents' stop nodes and the nodes that do not descend), read by
  // FrontQuery::update_bound. Spread over kStopSlots slots by block, so that the warps of a
  // launch do not all add to one address.
  unsigned long long yield[kStopSlots][2];
  // An update in place's front nodes dropped where they lay, per kind, spread as `yield`.
  unsigned long long dropped[kStopSlots][2];

  unsigned long long yield_of(int kind) const { return sum_of(yield, kind); }
  unsigned long long dropped_of(int kind) const { return sum_of(dropped, kind); }

 private:
  static unsigned long long sum_of(const unsigned long long (&slots)[kStopSlots][2], int kind) {
    unsigned long long s = 0;
    for (const auto& slot : slots) s += slot[kind];
    return s;
  }
};

struct FrontCounters {
  unsigned long long pairs;
  FrontQueryCounters query[kQueryCount];  // by Query
  InspectCounters inspect;  // pipeline c's inspection (front/quality.h)
};

}  // namespace cdb
