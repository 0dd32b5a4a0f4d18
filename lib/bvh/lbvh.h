#pragma once
#include <cstddef>
#include <cstdint>

#include "bvh/bvh_view.h"
#include "core/aabb.h"
#include "core/morton.h"
#include "exec/memory.h"

namespace cdb {

// Storage of one ordered LBVH and the scratch its build needs, all from the executor's
// memory. Sized once by reserve(num_leaves); a later reserve for more leaves is a logged
// growth.
template <class Exec>
struct Lbvh {
  explicit Lbvh(Exec& exec) {
    MemoryResource& mr = exec.memory();
    leaf_lo.bind(mr, "bvh.leaf_lo");
    leaf_hi.bind(mr, "bvh.leaf_hi");
    leaf_prim.bind(mr, "bvh.leaf_prim");
    leaf_parent.bind(mr, "bvh.leaf_parent");
    leaf_escape.bind(mr, "bvh.leaf_escape");
    node_lo.bind(mr, "bvh.node_lo");
    node_hi.bind(mr, "bvh.node_hi");
    node_left.bind(mr, "bvh.node_left");
    node_right.bind(mr, "bvh.node_right");
    node_parent.bind(mr, "bvh.node_parent");
    node_escape.bind(mr, "bvh.node_escape");
    node_first.bind(mr, "bvh.node_first");
    node_last.bind(mr, "bvh.node_last");
    count_log.bind(mr, "bvh.count_log");
    offset_log.bind(mr, "bvh.offset_log");
    prim_lo.bind(mr, "bvh.prim_lo");
    prim_hi.bind(mr, "bvh.prim_hi");
    centroid_box.bind(mr, "bvh.centroid_box");
    morton.bind(mr, "bvh.morton");
    morton_sorted.bind(mr, "bvh.morton_sorted");
    prim_iota.bind(mr, "bvh.prim_iota");
    build_lo.bind(mr, "bvh.build_lo");
    build_hi.bind(mr, "bvh.build_hi");
    build_left.bind(mr, "bvh.build_left");
    build_right.bind(mr, "bvh.build_right");
    build_parent.bind(mr, "bvh.build_parent");
    build_first.bind(mr, "bvh.build_first");
    build_last.bind(mr, "bvh.build_last");
    other_bound.bind(mr, "bvh.other_bound");
    new_index.bind(mr, "bvh.new_index");
    refit_flag.bind(mr, "bvh.refit_flag");
    temp.bind(mr, "bvh.temp");
  }

  void reserve(Exec& exec, uint32_t n) {
    num_leaves = n;
    const size_t internal = n > 1 ? n - 1 : 0;
    for (auto* a : {&leaf_lo, &leaf_hi, &prim_lo, &prim_hi, &build_lo, &build_hi}) a->reserve(n);
    for (auto* a : {&node_lo, &node_hi}) a->reserve(internal);
    for (auto* a : {&leaf_prim, &leaf_parent, &leaf_escape, &prim_iota}) a->reserve(n);
    for (auto* a : {&node_left, &node_right, &node_parent, &node_escape, &node_first, &node_last,
                    &build_left, &build_right, &build_parent, &build_first, &build_last,
                    &other_bound, &new_index, &refit_flag})
      a->reserve(internal);
    count_log.reserve(size_t(n) + 1);
    offset_log.reserve(size_t(n) + 1);
    morton.reserve(n);
    morton_sorted.reserve(n);
    centroid_box.reserve(1);
    size_t t = exec.sort_temp_bytes(n);
    t = t > exec.scan_temp_bytes(size_t(n) + 1) ? t : exec.scan_temp_bytes(size_t(n) + 1);
    t = t > exec.reduce_temp_bytes(n) ? t : exec.reduce_temp_bytes(n);
    temp.reserve(t > 256 ? t : 256);
  }

  BvhView view() const {
    return {num_leaves,       leaf_lo.data(),    leaf_hi.data(),    leaf_prim.data(),
            leaf_escape.data(), node_lo.data(),  node_hi.data(),    node_left.data(),
            node_right.data(), node_escape.data(), node_first.data(), node_last.data()};
  }

  uint32_t num_leaves = 0;
  MortonBits morton_bits = MortonBits::b63;

  // The ordered tree.
  Array<vec4f> leaf_lo, leaf_hi;
  Array<uint32_t> leaf_prim, leaf_parent, leaf_escape;
  Array<vec4f> node_lo, node_hi;
  Array<uint32_t> node_left, node_right, node_parent, node_escape, node_first, node_last;
  // Order log of the internal nodes (paper §3.2): count_log[l] is the LCL value of leaf l,
  // the number of internal nodes whose leftmost leaf is l; offset_log is its exclusive scan,
  // so internal nodes of segment l occupy [offset_log[l], offset_log[l+1]).
  Array<uint32_t> count_log, offset_log;

  // Build scratch: boxes in input order, Morton keys, the unordered tree.
  Array<vec4f> prim_lo, prim_hi;
  Array<Aabb<float>> centroid_box;
  Array<uint64_t> morton, morton_sorted;
  Array<uint32_t> prim_iota;
  Array<vec4f> build_lo, build_hi;
  Array<uint32_t> build_left, build_right, build_parent, build_first, build_last;
  Array<uint32_t> other_bound, new_index, refit_flag;
  Array<std::byte> temp;
};

}  // namespace cdb
