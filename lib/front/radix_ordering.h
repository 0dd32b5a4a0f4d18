#pragma once
// The radix-sort baseline of the paper's Fig. 6: the same front order as the histogram sort
// (by BVH node key, prune-marked before sprout-marked within a node), obtained by a CUB /
// host radix sort of (2 j + mark) keys and a gather. It needs the front's size on the host.
#include <algorithm>
#include <cstdint>

#include "cdbench/exec/balance.h"
#include "cdbench/exec/gather.h"
#include "cdbench/exec/memory.h"
#include "cdbench/front/front.h"

namespace cdb {

struct RadixKeyFn {
  const uint32_t* node;
  const uint8_t* mark;
  uint64_t* keys;
  uint32_t* iota;
  CDB_HD void operator()(uint32_t e) const {
    keys[e] = (uint64_t(ref_index(node[e])) << 1) | mark[e];
    iota[e] = e;
  }
};

// Scratch of the radix path, sized for a front capacity.
template <class Exec>
struct RadixScratch {
  void bind(MemoryResource& mr) {
    bind_arrays(mr, "radix.",
                {{&keys, "keys"}, {&keys_sorted, "keys_sorted"}, {&iota, "iota"}, {&perm, "perm"}, {&temp, "temp"}});
  }
  void reserve(Exec& exec, size_t capacity) {
    keys.reserve(capacity);
    keys_sorted.reserve(capacity);
    iota.reserve(capacity);
    perm.reserve(capacity);
    temp.reserve(std::max<size_t>(256, exec.sort_temp_bytes(capacity)));
  }
  Array<uint64_t> keys, keys_sorted;
  Array<uint32_t> iota, perm;
  Array<std::byte> temp;
};

// Sorts n front nodes (prim, node, mark) into out_prim, out_node; key_bits covers 2 * segments.
template <class Exec>
void radix_order_front(Exec& exec, RadixScratch<Exec>& r, size_t n, int key_bits, const uint32_t* prim,
                       const uint32_t* node, const uint8_t* mark, uint32_t* out_prim, uint32_t* out_node) {
  if (n == 0) return;
  // Counted growth, with headroom. The sort's temporary storage is checked apart: a second
  // set_topology re-reserves the arrays for the initial capacity, which leaves the keys
  // large but sizes the temporary storage for fewer keys.
  if (n > r.keys.capacity() || exec.sort_temp_bytes(n) > r.temp.size())
    r.reserve(exec, std::max(n + n / 4, r.keys.capacity()));
  exec.for_each_n(n, RadixKeyFn{node, mark, r.keys.data(), r.iota.data()});
  exec.sort_pairs(r.keys.data(), r.keys_sorted.data(), r.iota.data(), r.perm.data(), n, key_bits,
                  r.temp.data(), r.temp.size());
  gather(exec, n, r.perm.data(), prim, node, out_prim, out_node);
}

}  // namespace cdb
