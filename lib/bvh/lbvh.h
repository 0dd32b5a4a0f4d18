#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "bvh/bvh_view.h"
#include "core/aabb.h"
#include "core/morton.h"
#include "exec/memory.h"

namespace cdb {

// Leaves per refit tile (bvh/refit.h); the largest tree whose spanning top refits in one
// block (bvh/refit_top.h), past which handing the top over between blocks is faster (H100:
// refit 32 -> 21 us on funnel's 8.7K leaves, 39 -> 31 us on cloth-wave's 32K, but 49 -> 65 us
// on cloth-ball's 93K and 52 -> 115 us on n-body's 148K); and the spanning nodes the block
// keeps in shared memory (about 3.4% of the internal nodes span tiles: 1,100 at 2^15 leaves).
inline constexpr uint32_t kRefitTile = 256;
inline constexpr uint32_t kRefitTopMaxLeaves = 1u << 15;
inline constexpr uint32_t kRefitTopSharedSlots = 1536;

// Storage of one ordered LBVH and the scratch its build needs, all from the executor's
// memory. Sized once by reserve(num_leaves); a later reserve for more leaves is a logged
// growth.
template <class Exec>
struct Lbvh {
  // `name` prefixes the buffers' names in the growth log (a scene may have two trees).
  explicit Lbvh(Exec& exec, const std::string& name = "bvh") {
    MemoryResource& mr = exec.memory();
    leaf_lo.bind(mr, name + ".leaf_lo");
    leaf_hi.bind(mr, name + ".leaf_hi");
    leaf_prim.bind(mr, name + ".leaf_prim");
    leaf_parent.bind(mr, name + ".leaf_parent");
    leaf_escape.bind(mr, name + ".leaf_escape");
    node_lo.bind(mr, name + ".node_lo");
    node_hi.bind(mr, name + ".node_hi");
    node_left.bind(mr, name + ".node_left");
    node_right.bind(mr, name + ".node_right");
    node_parent.bind(mr, name + ".node_parent");
    node_escape.bind(mr, name + ".node_escape");
    node_first.bind(mr, name + ".node_first");
    node_last.bind(mr, name + ".node_last");
    count_log.bind(mr, name + ".count_log");
    offset_log.bind(mr, name + ".offset_log");
    prim_lo.bind(mr, name + ".prim_lo");
    prim_hi.bind(mr, name + ".prim_hi");
    centroid_box.bind(mr, name + ".centroid_box");
    morton.bind(mr, name + ".morton");
    morton_sorted.bind(mr, name + ".morton_sorted");
    prim_iota.bind(mr, name + ".prim_iota");
    build_lo.bind(mr, name + ".build_lo");
    build_hi.bind(mr, name + ".build_hi");
    build_left.bind(mr, name + ".build_left");
    build_right.bind(mr, name + ".build_right");
    build_parent.bind(mr, name + ".build_parent");
    build_first.bind(mr, name + ".build_first");
    build_last.bind(mr, name + ".build_last");
    other_bound.bind(mr, name + ".other_bound");
    new_index.bind(mr, name + ".new_index");
    refit_flag.bind(mr, name + ".refit_flag");
    span_flag.bind(mr, name + ".span_flag");
    span_scan.bind(mr, name + ".span_scan");
    span_count.bind(mr, name + ".span_count");
    span_node.bind(mr, name + ".span_node");
    span_parent.bind(mr, name + ".span_parent");
    span_child.bind(mr, name + ".span_child");
    span_lo.bind(mr, name + ".span_lo");
    span_hi.bind(mr, name + ".span_hi");
    temp.bind(mr, name + ".temp");
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
    // refit.h counts arrivals without resetting them: every build zeroes them here.
    exec.fill(refit_flag.data(), internal, 0u);
    if (refit_top_fits()) {
      for (auto* a : {&span_flag, &span_scan, &span_node, &span_parent}) a->reserve(internal);
      span_child.reserve(2 * internal);
      span_lo.reserve(2 * internal);
      span_hi.reserve(2 * internal);
      span_count.reserve(1);
    }
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
  // Refit the nodes spanning tiles in one block (bvh/refit_top.h) when the tree allows;
  // false: hand them over between blocks (tests compare the two).
  bool refit_top_in_block = true;
  // Spanning nodes kept in shared memory, at most kRefitTopSharedSlots; the rest in global
  // memory (tests lower it to cover that path).
  uint32_t refit_top_shared_slots = kRefitTopSharedSlots;
  bool refit_top_fits() const { return num_leaves > kRefitTile && num_leaves <= kRefitTopMaxLeaves; }

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
  // The spanning nodes' index for refit_top.h (only for trees where refit_top_fits()).
  Array<uint32_t> span_flag, span_scan, span_count, span_node, span_parent, span_child;
  Array<vec4f> span_lo, span_hi;
  Array<std::byte> temp;
};

}  // namespace cdb
