#pragma once
// Two arrays put into a new order by one permutation: out_a[k] = a[order[k]] and
// out_b[k] = b[order[k]]. Every sort here sorts indices and then gathers what goes with
// them: the sweep's sorted boxes, the hash's sorted
// entries, the radix-ordered front.
#include <cstddef>
#include <cstdint>

#include "cdbench/core/hd.h"

namespace cdb {

template <class A, class B>
struct GatherFn {
  const uint32_t* order;
  const A* a;
  const B* b;
  A* out_a;
  B* out_b;
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t p = order[k];
    out_a[k] = a[p];
    out_b[k] = b[p];
  }
};

template <class Exec, class A, class B>
void gather(Exec& exec, size_t n, const uint32_t* order, const A* a, const B* b, A* out_a, B* out_b) {
  exec.for_each_n(n, GatherFn<A, B>{order, a, b, out_a, out_b});
}

}  // namespace cdb
