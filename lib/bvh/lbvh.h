#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "bvh/bvh_view.h"
#include "bvh/refit_tiles.h"
#include "core/aabb.h"
#include "core/morton.h"
#include "exec/memory.h"

namespace cdb {

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
    tile_start.bind(mr, name + ".tile_start");
    tile_scan.bind(mr, name + ".tile_scan");
    tile_first.bind(mr, name + ".tile_first");
    tile_count.bind(mr, name + ".tile_count");
    span_flag.bind(mr, name + ".span_flag");
    span_scan.bind(mr, name + ".span_scan");
    span_count.bind(mr, name + ".span_count");
    span_node.bind(mr, name + ".span_node");
    span_parent.bind(mr, name + ".span_parent");
    span_child.bind(mr, name + ".span_child");
    span_depth.bind(mr, name + ".span_depth");
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
    tile_start.reserve(n);
    tile_scan.reserve(n);
    tile_first.reserve(size_t(n) + 1);
    tile_count.reserve(1);
    if (refit_top_fits()) {
      for (auto* a : {&span_flag, &span_scan, &span_node, &span_parent, &span_depth}) a->reserve(internal);
      span_child.reserve(2 * internal);
      span_lo.reserve(2 * internal);
      span_hi.reserve(2 * internal);
      span_count.reserve(2);
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
    return {num_leaves,        leaf_lo.data(),    leaf_hi.data(),   node_lo.data(),
            node_hi.data(),    node_right.data(), node_first.data(), node_last.data()};
  }

  uint32_t num_leaves = 0;
  MortonBits morton_bits = MortonBits::b63;
  // Trees of up to this many leaves refit the nodes spanning tiles in one block
  // (bvh/refit_top.h); larger ones, or all with 0, hand them over between blocks (tests
  // compare the two). Set before reserve, which sizes the spanning index.
  uint32_t refit_top_max_leaves = kRefitTopMaxLeaves;
  // Spanning nodes kept in shared memory, at most kRefitTopSharedSlots; the rest in global
  // memory (tests lower it to cover that path).
  uint32_t refit_top_shared_slots = kRefitTopSharedSlots;
  bool refit_top_fits() const { return num_leaves > kRefitTile && num_leaves <= refit_top_max_leaves; }

  // The ordered tree.
  Array<vec4f> leaf_lo, leaf_hi;
  Array<uint32_t> leaf_prim, leaf_parent, leaf_escape;
  Array<vec4f> node_lo, node_hi;
  Array<uint32_t> node_left, node_right, node_parent, node_escape, node_first, node_last;
  // Order log of the internal nodes (paper §3.2): count_log[l] is the LCL value of leaf l,
  // the number of internal nodes whose leftmost leaf is l; offset_log is its exclusive scan,
  // so internal nodes of segment l occupy [offset_log[l], offset_log[l+1]).
  Array<uint32_t> count_log, offset_log;

  // Build scratch: boxes in input order, Morton keys, the unordered tree. A restructure,
  // which replaces a build on its frame, borrows part of it (bvh/restructure.h).
  Array<vec4f> prim_lo, prim_hi;
  Array<Aabb<float>> centroid_box;
  Array<uint64_t> morton, morton_sorted;
  Array<uint32_t> prim_iota;
  Array<vec4f> build_lo, build_hi;
  Array<uint32_t> build_left, build_right, build_parent, build_first, build_last;
  Array<uint32_t> other_bound, new_index, refit_flag;
  // The refit's tiles (bvh/refit_index.h): treelet marks per leaf, their scan, each tile's
  // first leaf (and n after the last), the number of tiles.
  Array<uint32_t> tile_start, tile_scan, tile_first, tile_count;
  // Blocks of the refit's tile kernel: twice the tiles of kRefitTile leaves (treelets were
  // 1.6 times as many on the 32K cloth); a block refits its tile and every tile that many
  // further on, so a tree with more treelets refits more slowly, never wrongly.
  uint32_t refit_tile_blocks() const {
    const uint32_t blocks = 2 * ((num_leaves + kRefitTile - 1) / kRefitTile) + 2;
    return blocks < num_leaves ? blocks : num_leaves;
  }
  // The spanning nodes' index for refit_top.h (only for trees where refit_top_fits()).
  Array<uint32_t> span_flag, span_scan, span_count, span_node, span_parent, span_child, span_depth;
  Array<vec4f> span_lo, span_hi;
  Array<std::byte> temp;
};

}  // namespace cdb
