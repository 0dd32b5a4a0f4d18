#pragma once
#include <cstdint>

#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

// Boxes put into a new order: out[k] = in[order[k]] (sorted leaves, sorted sweep boxes).
struct GatherBoxesFn {
  const uint32_t* order;
  const vec4f* lo;
  const vec4f* hi;
  vec4f* out_lo;
  vec4f* out_hi;
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t p = order[k];
    out_lo[k] = lo[p];
    out_hi[k] = hi[p];
  }
};

}  // namespace cdb
