#pragma once
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>

#include "cdbench/bvh/bvh_view.h"
#include "cdbench/bvh/refit_tiles.h"
#include "cdbench/bvh/tree_arrays.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/morton.h"
#include "cdbench/exec/memory.h"

namespace cdb {

// Whether a tree holds its build scratch or borrows another's (Lbvh::build_scratch).
enum class BuildScratch { own, lent };

// Storage of one ordered LBVH and the scratch its build needs, all from the executor's
// memory. Sized once by reserve(num_leaves); a later reserve for more leaves is a logged
// growth.
template <class Exec>
struct Lbvh {
  // `name` prefixes the buffers' names in the growth log (a scene may have two trees).
  explicit Lbvh(Exec& exec, const std::string& name = "bvh") {
    MemoryResource& mr = exec.memory();
    const std::string p = name + ".";
    each_array([&](auto array, const char* buffer) { (this->*array).bind(mr, p + buffer); });
  }

  void reserve(Exec& exec, uint32_t n) {
    num_leaves = n;
    const size_t internal = n > 1 ? n - 1 : 0;
    leaf_box.reserve(n);
    node_box.reserve(internal);
    for (auto* a : {&leaf_prim, &leaf_parent, &leaf_escape, &tile_start, &tile_scan}) a->reserve(n);
    for (auto* a : {&node_left, &node_right, &node_parent, &node_escape, &node_first, &node_last, &refit_flag})
      a->reserve(internal);
    // refit.h counts arrivals without resetting them: every build zeroes them here.
    exec.fill(refit_flag.data(), internal, 0u);
    for (auto* a : {&tile_first, &count_log, &offset_log}) a->reserve(size_t(n) + 1);
    tile_count.reserve(1);
    if (refit_top_fits()) {
      for (auto* a : {&span_flag, &span_scan, &span_node, &span_parent, &span_depth}) a->reserve(internal);
      span_child.reserve(2 * internal);
      span_lo.reserve(2 * internal);
      span_hi.reserve(2 * internal);
      span_count.reserve(2);
    }
    if (refit_levels) {
      for (auto* a : {&level_node, &level_code}) a->reserve(n);
      level_link.reserve(2 * size_t(n));
    }
    if (build_scratch == BuildScratch::own) reserve_build_scratch(exec, n);
  }

  // The boxes alone, for `n` leaves: a tree that holds a copy of another's boxes and is
  // traversed through that one's links (an update ahead: pipeline/front_pipeline.h).
  // reserve() reserves the rest later where the tree is built after all.
  void reserve_boxes(uint32_t n) {
    num_leaves = n;
    leaf_box.reserve(n);
    node_box.reserve(n > 1 ? n - 1 : 0);
  }

  // Exchanges the build scratch with `o`'s: a tree of lent scratch borrows that of a tree
  // of as many leaves that builds nothing meanwhile, and gives it back the same way.
  void swap_build_scratch(Lbvh& o) {
    each_scratch_array([&](auto array, const char*) { std::swap(this->*array, o.*array); });
  }

  // Exchanges every buffer and size with `o` (a tree built ahead replaces the current one:
  // pipeline/front_pipeline.h); the build settings below stay, the two trees share them.
  void swap(Lbvh& o) {
    std::swap(num_leaves, o.num_leaves);
    std::swap(morton_bits, o.morton_bits);
    each_array([&](auto array, const char*) { std::swap(this->*array, o.*array); });
  }

  BvhView view() const {
    return {num_leaves, leaf_box.data(), node_box.data(), node_right.data(), node_first.data(), node_last.data()};
  }

  TreeArrays tree() {
    return {leaf_box.data(),   leaf_prim.data(),   leaf_parent.data(), leaf_escape.data(), node_box.data(),
            node_left.data(),  node_right.data(),  node_parent.data(), node_escape.data(), node_first.data(),
            node_last.data()};
  }
  BuildArrays build() {
    return {build_lo.data(),    build_hi.data(),    build_left.data(), build_right.data(),
            build_parent.data(), build_first.data(), build_last.data(), other_bound.data(),
            count_log.data(),   offset_log.data(),  new_index.data()};
  }
  // span_flag is null where the top is not indexed (refit_top_fits()).
  RefitIndexArrays refit_index() {
    return {tile_start.data(), tile_scan.data(),  tile_first.data(),
            tile_count.data(), refit_top_fits() ? span_flag.data() : nullptr,
            span_scan.data(),  span_count.data(), span_node.data(),
            span_parent.data(), span_child.data(), span_depth.data(),
            span_lo.data(),    span_hi.data(),    level_node.data(),
            level_code.data(), level_link.data()};
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
  // The refit's tiles level by level (bvh/refit_levels.h, --refit-levels) instead of the
  // climb with hand-overs (bvh/refit.h); tests compare the two. Set before reserve. By
  // default as --refit-levels auto: on the GPU, not on the host.
  bool refit_levels = Exec::is_device;
  // Whether reserve gives the tree its own build scratch. A tree built ahead (--rebuild-ahead)
  // borrows the current tree's for its build (swap_build_scratch), which only refits
  // meanwhile: a build ahead then costs the tree, not its scratch too (126 bytes a leaf).
  BuildScratch build_scratch = BuildScratch::own;

  // The ordered tree.
  Array<NodeBox> leaf_box;
  Array<uint32_t> leaf_prim, leaf_parent, leaf_escape;
  Array<NodeBox> node_box;
  Array<uint32_t> node_left, node_right, node_parent, node_escape, node_first, node_last;
  // Order log of the internal nodes (paper §3.2): count_log[l] is the LCL value of leaf l,
  // the number of internal nodes whose leftmost leaf is l; offset_log is its exclusive scan,
  // so internal nodes of segment l occupy [offset_log[l], offset_log[l+1]).
  Array<uint32_t> count_log, offset_log;

  // Build scratch: boxes in input order, Morton keys, the unordered tree, the sorts' and
  // scans' temporary storage (the tiles' index at a build, the fronts' ordering of this
  // tree: pipeline/front_query.h). A restructure, which replaces a build on its frame,
  // borrows part of it (bvh/restructure.h); so does a tree built ahead (build_scratch).
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
  // The tiles' tables for refit_levels, by split (bvh/refit_levels.h).
  Array<uint32_t> level_node, level_code, level_link;
  Array<std::byte> temp;

 private:
  void reserve_build_scratch(Exec& exec, uint32_t n) {
    const size_t internal = n > 1 ? n - 1 : 0;
    for (auto* a : {&prim_lo, &prim_hi, &build_lo, &build_hi}) a->reserve(n);
    prim_iota.reserve(n);
    for (auto* a : {&build_left, &build_right, &build_parent, &build_first, &build_last, &other_bound, &new_index})
      a->reserve(internal);
    for (auto* a : {&morton, &morton_sorted}) a->reserve(n);
    centroid_box.reserve(1);
    size_t t = exec.sort_temp_bytes(n);
    t = t > exec.scan_temp_bytes(size_t(n) + 1) ? t : exec.scan_temp_bytes(size_t(n) + 1);
    t = t > exec.reduce_temp_bytes(n) ? t : exec.reduce_temp_bytes(n);
    temp.reserve(t > 256 ? t : 256);
  }

  // Every buffer with its name, as f(&Lbvh::buffer, "buffer"): one list for the constructor's
  // binding and for swap, so that neither can leave one out; the build scratch's its own
  // list (swap_build_scratch).
  template <class F>
  static void each_array(F&& f) {
    f(&Lbvh::leaf_box, "leaf_box");
    f(&Lbvh::node_box, "node_box");
    for (auto [array, buffer] : {std::pair{&Lbvh::span_lo, "span_lo"}, {&Lbvh::span_hi, "span_hi"}})
      f(array, buffer);
    for (auto [array, buffer] :
         {std::pair{&Lbvh::leaf_prim, "leaf_prim"}, {&Lbvh::leaf_parent, "leaf_parent"},
          {&Lbvh::leaf_escape, "leaf_escape"}, {&Lbvh::node_left, "node_left"}, {&Lbvh::node_right, "node_right"},
          {&Lbvh::node_parent, "node_parent"}, {&Lbvh::node_escape, "node_escape"},
          {&Lbvh::node_first, "node_first"}, {&Lbvh::node_last, "node_last"}, {&Lbvh::count_log, "count_log"},
          {&Lbvh::offset_log, "offset_log"}, {&Lbvh::refit_flag, "refit_flag"},
          {&Lbvh::tile_start, "tile_start"}, {&Lbvh::tile_scan, "tile_scan"}, {&Lbvh::tile_first, "tile_first"},
          {&Lbvh::tile_count, "tile_count"}, {&Lbvh::span_flag, "span_flag"}, {&Lbvh::span_scan, "span_scan"},
          {&Lbvh::span_count, "span_count"}, {&Lbvh::span_node, "span_node"}, {&Lbvh::span_parent, "span_parent"},
          {&Lbvh::span_child, "span_child"}, {&Lbvh::span_depth, "span_depth"},
          {&Lbvh::level_node, "level_node"}, {&Lbvh::level_code, "level_code"}, {&Lbvh::level_link, "level_link"}})
      f(array, buffer);
    each_scratch_array(f);
  }
  template <class F>
  static void each_scratch_array(F&& f) {
    for (auto [array, buffer] : {std::pair{&Lbvh::prim_lo, "prim_lo"}, {&Lbvh::prim_hi, "prim_hi"},
                                 {&Lbvh::build_lo, "build_lo"}, {&Lbvh::build_hi, "build_hi"}})
      f(array, buffer);
    for (auto [array, buffer] :
         {std::pair{&Lbvh::prim_iota, "prim_iota"}, {&Lbvh::build_left, "build_left"},
          {&Lbvh::build_right, "build_right"}, {&Lbvh::build_parent, "build_parent"},
          {&Lbvh::build_first, "build_first"}, {&Lbvh::build_last, "build_last"},
          {&Lbvh::other_bound, "other_bound"}, {&Lbvh::new_index, "new_index"}})
      f(array, buffer);
    f(&Lbvh::morton, "morton");
    f(&Lbvh::morton_sorted, "morton_sorted");
    f(&Lbvh::centroid_box, "centroid_box");
    f(&Lbvh::temp, "temp");
  }
};

}  // namespace cdb
