#pragma once
// What the sort-and-sweep baselines (sweep and example-sap) keep per box, and the step they
// share on it: the face boxes (face_boxes.h), then the boxes' indices radix-sorted by one
// coordinate of their minimum corner, the axis each sweep walks along. Each workspace
// derives from this; sweep adds its axis choice and the boxes gathered into sorted order.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>

#include "baselines/common/face_boxes.h"
#include "cdbench/core/float_bits.h"
#include "cdbench/exec/memory.h"

namespace cdb {

// A float as an unsigned integer of the same order, for the radix sort: positives get the
// sign bit set, negatives all bits flipped. -0 sorts just before +0; they compare equal as
// floats, so the sorted minima stay non-decreasing, which is all a sweep needs.
CDB_HD_INLINE uint32_t ordered_key(float f) {
  const uint32_t bits = float_bits(f);
  return (bits & 0x80000000u) ? ~bits : (bits | 0x80000000u);
}

// Per box: the key of its minimum corner's coordinate `coord` picks, and its index.
template <class Coord>
struct BoxKeyFn {
  Coord coord;
  const vec4f* lo;
  uint64_t* keys;
  uint32_t* iota;
  CDB_HD void operator()(uint32_t i) const {
    keys[i] = ordered_key(coord(lo[i]));
    iota[i] = i;
  }
};

template <class Exec>
struct SortedBoxes : FaceBoxes {
  // Buffers are named "<prefix>.<array>" in the growth log.
  SortedBoxes(Exec& exec, const std::string& prefix) : FaceBoxes(exec.memory(), prefix) {
    bind_arrays(exec.memory(), prefix + ".",
                {{&keys, "keys"}, {&sorted_keys, "sorted_keys"}, {&iota, "iota"}, {&order, "order"}, {&temp, "temp"}});
  }

  // Sized once from the triangle count; the temporary storage also holds `other_temp_bytes`
  // for what else the workspace runs in it.
  void reserve(Exec& exec, uint32_t n, size_t other_temp_bytes = 0) {
    reserve_faces(n);
    for (auto* a : {&keys, &sorted_keys}) a->reserve(n);
    for (auto* a : {&iota, &order}) a->reserve(n);
    temp.reserve(std::max(exec.sort_temp_bytes(n), other_temp_bytes));  // queried CUB style
  }

  Array<uint64_t> keys, sorted_keys;
  Array<uint32_t> iota, order;  // order[k]: the box of the k-th smallest key
  Array<std::byte> temp;
};

// The n boxes sorted by the coordinate `coord` (a CDB_HD functor, vec4f -> float) picks of
// their minimum corners; the sort is stable, so equal keys keep the boxes' order.
template <class Exec, class Coord>
void sort_boxes(Exec& exec, SortedBoxes<Exec>& s, uint32_t n, const Coord& coord) {
  if (n == 0) return;
  exec.for_each_n(n, BoxKeyFn<Coord>{coord, s.lo.data(), s.keys.data(), s.iota.data()});
  exec.sort_pairs(s.keys.data(), s.sorted_keys.data(), s.iota.data(), s.order.data(), n, 32,
                  s.temp.data(), s.temp.size());
}

}  // namespace cdb
