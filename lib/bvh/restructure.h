#pragma once
// Subtree restructuring (paper §4.2): each candidate subtree — internal node r covering
// sorted leaves [s, t] — is rebuilt from its own leaves only, by Apetrei's method bottom-up
// until r is met, and laid out depth-first in place. Leaves outside every candidate, and
// every node outside the candidates' subtrees, keep their index, box and links: r keeps its
// index, its leaf range, its parent and its escape, and so its box (the union of the same
// leaves). Within a candidate the leaves are re-sorted by a Morton code normalized to r's
// box, which is what recovers quality after the mesh deformed away from the build's order.
//
// All candidates are restructured together: one key sort over the candidates' leaves (the
// candidate's slot in the high bits keeps each within its range), one climb, one scan.
// The candidate list comes from the quality inspection of an earlier frame
// (front/quality.h); the host knows its size from that frame's read-back, so nothing here
// reads back.
#include <cstdint>

#include "cdbench/bvh/build.h"
#include "cdbench/bvh/lbvh.h"
#include "cdbench/bvh/node_ref.h"
#include "cdbench/bvh/order.h"
#include "cdbench/bvh/refit_index.h"
#include "cdbench/core/atomics.h"
#include "cdbench/core/morton.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/memory.h"

namespace cdb {

// Morton bits of a leaf's key within its candidate; the candidate slot takes the bits above.
inline constexpr int kRestructureCodeBits = 30;

// The candidates as the front restructure (front/restructure_front.h) and the kernels here
// see them. Slot k describes the subtree rooted at node[k] over leaves [first[k], last[k]];
// leaf_slot[l + 1] is k + 1 when leaf l is inside candidate k, 0 otherwise.
struct CandidateView {
  const uint32_t* node;
  const uint32_t* first;
  const uint32_t* last;
  const uint32_t* escape;
  const uint32_t* leaf_slot;

  CDB_HD_INLINE uint32_t slot_of_leaf(uint32_t l) const { return leaf_slot[l + 1]; }
};

// The candidates and the restructure's scratch as its kernels see them
// (RestructureScratch::arrays). Entry m of the key sort belongs to candidate
// candidate_of(m); its leaf was old_leaf_sorted[m] and becomes new_leaf[m].
struct RestructureArrays {
  uint32_t *node, *first, *last, *escape, *parent, *size, *base, *leaf_tag, *leaf_slot;
  uint64_t* keys_sorted;
  uint32_t *old_leaf_sorted, *new_leaf, *moved_prim;
  // Borrowed from the tree's build scratch: the key sort's input keys and leaf numbers, the
  // moved leaves' boxes, and the keys by new leaf position for the climb.
  uint64_t* keys;
  uint32_t* old_leaf;
  vec4f *moved_lo, *moved_hi;
  uint64_t* keys_by_leaf;

  CDB_HD_INLINE CandidateView candidates() const { return {node, first, last, escape, leaf_slot}; }
  CDB_HD_INLINE uint32_t candidate_of(uint32_t m) const { return uint32_t(keys_sorted[m] >> kRestructureCodeBits); }
};

// Candidate list and restructure scratch, sized once per topology. The scratch a
// restructure shares with nothing else is here; the rest it takes from the tree's build
// scratch, which no restructure frame builds with (a restructure replaces a rebuild): the
// key sort's input keys in `morton_sorted`, its input leaf numbers in `prim_iota`, the moved
// leaves' boxes in `prim_lo` and `prim_hi`, the sort's and scans' storage in `temp`. That
// saves 57 bytes a leaf (28 MiB on the 522K cloth).
template <class Exec>
struct RestructureScratch {
  explicit RestructureScratch(Exec& exec) {
    bind_arrays(exec.memory(), "restructure.",
                {{&node, "candidate_node"}, {&first, "candidate_first"}, {&last, "candidate_last"},
                 {&escape, "candidate_escape"}, {&parent, "candidate_parent"}, {&size, "candidate_size"},
                 {&base, "candidate_base"}, {&leaf_tag, "leaf_tag"}, {&leaf_slot, "leaf_slot"},
                 {&keys_sorted, "keys_sorted"}, {&old_leaf_sorted, "old_leaf_sorted"}, {&new_leaf, "new_leaf"},
                 {&moved_prim, "moved_prim"}});
  }

  // Candidates are disjoint subtrees of at least min_leaves leaves each.
  void reserve(uint32_t num_leaves, uint32_t min_leaves) {
    max_candidates = num_leaves / (min_leaves > 1 ? min_leaves : 1) + 1;
    for (auto* a : {&node, &first, &last, &escape, &parent}) a->reserve(max_candidates);
    for (auto* a : {&size, &base}) a->reserve(size_t(max_candidates) + 1);
    for (auto* a : {&leaf_tag, &leaf_slot}) a->reserve(size_t(num_leaves) + 1);
    keys_sorted.reserve(num_leaves);
    for (auto* a : {&old_leaf_sorted, &new_leaf, &moved_prim}) a->reserve(num_leaves);
  }

  CandidateView view() const {
    return {node.data(), first.data(), last.data(), escape.data(), leaf_slot.data()};
  }

  // The kernels' view: this scratch and what it borrows from `bvh`'s build scratch.
  RestructureArrays arrays(Lbvh<Exec>& bvh) {
    return {node.data(),         first.data(),           last.data(),          escape.data(),
            parent.data(),       size.data(),            base.data(),          leaf_tag.data(),
            leaf_slot.data(),    keys_sorted.data(),     old_leaf_sorted.data(), new_leaf.data(),
            moved_prim.data(),   bvh.morton_sorted.data(), bvh.prim_iota.data(), bvh.prim_lo.data(),
            bvh.prim_hi.data(),  bvh.morton.data()};
  }

  uint32_t max_candidates = 0;
  Array<uint32_t> node, first, last, escape, parent, size, base;
  Array<uint32_t> leaf_tag, leaf_slot;
  Array<uint64_t> keys_sorted;
  Array<uint32_t> old_leaf_sorted, new_leaf, moved_prim;
};

// Per candidate: its range, escape and parent from the current tree, and a +(k+1) / -(k+1)
// step at its range ends so that a scan tags every leaf with its candidate (ranges are
// disjoint, so at most one step is open at any leaf).
struct DescribeCandidateFn {
  TreeArrays tree;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t k) const {
    const uint32_t r = rs.node[k], s = tree.node_first[r], t = tree.node_last[r];
    rs.first[k] = s;
    rs.last[k] = t;
    rs.escape[k] = tree.node_escape[r];
    rs.parent[k] = tree.node_parent[r];
    rs.size[k] = t - s + 1;
    atomic_add_relaxed(&rs.leaf_tag[s], k + 1);
    atomic_add_relaxed(&rs.leaf_tag[t + 1], 0u - (k + 1));
  }
};

// Key of every candidate leaf: slot above a 30-bit Morton code of its centroid in the
// candidate root's (refitted) box; value: the leaf's current position.
struct RestructureKeyFn {
  TreeArrays tree;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t l) const {
    const uint32_t tag = rs.candidates().slot_of_leaf(l);
    if (tag == 0) return;
    const uint32_t k = tag - 1, r = rs.node[k];
    const NodeBox leaf = tree.leaf_box[l], root = tree.node_box[r];
    const vec4f u = unit_centroid(leaf.lo, leaf.hi, root.lo, root.hi);
    const uint32_t m = rs.base[k] + (l - rs.first[k]);
    rs.keys[m] = (uint64_t(k) << kRestructureCodeBits) | morton_code(u, MortonBits::b30);
    rs.old_leaf[m] = l;
  }
};

// Sorted entry m goes to leaf position first + (m - base) of its candidate. Moving goes
// through scratch (leaves are permuted in place).
struct GatherMovedLeavesFn {
  TreeArrays tree;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t m) const {
    const uint32_t k = rs.candidate_of(m);
    rs.new_leaf[m] = rs.first[k] + (m - rs.base[k]);
    const uint32_t old = rs.old_leaf_sorted[m];
    rs.moved_prim[m] = tree.leaf_prim[old];
    const NodeBox b = tree.leaf_box[old];
    rs.moved_lo[m] = b.lo;
    rs.moved_hi[m] = b.hi;
  }
};

struct PlaceMovedLeavesFn {
  TreeArrays tree;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t m) const {
    const uint32_t p = rs.new_leaf[m];
    tree.leaf_prim[p] = rs.moved_prim[m];
    tree.leaf_box[p] = {rs.moved_lo[m], rs.moved_hi[m]};
    rs.keys_by_leaf[p] = rs.keys_sorted[m];
  }
};

struct SubtreeClimbFn {
  ApetreiTree tree;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t m) const {
    const uint32_t k = rs.candidate_of(m);
    apetrei_climb(tree, rs.new_leaf[m], rs.first[k], rs.last[k]);
  }
};

// Depth-first indices of a subtree's nodes start at its root's index r: segment l of the
// subtree begins at r + (offset_log[l] - offset_log[s]).
struct SubtreeLayoutFn {
  DepthFirstLayout layout;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t m) const {
    const uint32_t k = rs.candidate_of(m);
    const uint32_t l = rs.new_leaf[m];
    const uint32_t* offset_log = layout.build.offset_log;
    layout.number_chain(l, rs.node[k] + (offset_log[l] - offset_log[rs.first[k]]));
  }
};

struct SubtreePlaceFn {
  DepthFirstLayout layout;
  RestructureArrays rs;
  CDB_HD void operator()(uint32_t m) const {
    const uint32_t k = rs.candidate_of(m);
    const uint32_t l = rs.new_leaf[m], t = rs.last[k];
    // Internal node l (split after leaf l) exists for every leaf of the range but the last.
    if (l != t) layout.place_node(l, t, rs.escape[k], rs.parent[k]);
    layout.link_leaf(l, t, rs.escape[k]);
  }
};

// Describes the `count` candidates listed in scratch.node from the current tree and tags
// their leaves. Runs before the front restructure reads the old node ranges.
template <class Exec>
void describe_candidates(Exec& exec, Lbvh<Exec>& bvh, RestructureScratch<Exec>& rs,
                         uint32_t count) {
  const uint32_t n = bvh.num_leaves;
  if (count == 0 || n < 2) return;
  exec.fill(rs.leaf_tag.data(), size_t(n) + 1, 0u);
  exec.fill(rs.size.data() + count, 1, 0u);
  exec.for_each_n(count, DescribeCandidateFn{bvh.tree(), rs.arrays(bvh)});
  exec.exclusive_scan(rs.leaf_tag.data(), rs.leaf_slot.data(), size_t(n) + 1, bvh.temp.data(),
                      bvh.temp.size());
  exec.exclusive_scan(rs.size.data(), rs.base.data(), size_t(count) + 1, bvh.temp.data(),
                      bvh.temp.size());
}

// Restructures the described candidates (`leaves` leaves in all). The tree must be
// refitted to the current frame first: keys come from its boxes. Leaves of the candidates
// change position; the scratch keeps which leaf is in which candidate (view().leaf_slot)
// for the front restructure.
template <class Exec>
void restructure_subtrees(Exec& exec, Lbvh<Exec>& bvh, RestructureScratch<Exec>& rs,
                          uint32_t count, uint32_t leaves) {
  const uint32_t n = bvh.num_leaves;
  if (count == 0 || n < 2) return;
  const TreeArrays tree = bvh.tree();
  const RestructureArrays arrays = rs.arrays(bvh);
  exec.for_each_n(n, RestructureKeyFn{tree, arrays});
  int slot_bits = 1;
  while ((uint64_t(1) << slot_bits) < count) ++slot_bits;
  exec.sort_pairs(bvh.morton_sorted.data(), rs.keys_sorted.data(), bvh.prim_iota.data(),
                  rs.old_leaf_sorted.data(), leaves, kRestructureCodeBits + slot_bits,
                  bvh.temp.data(), bvh.temp.size());
  exec.for_each_n(leaves, GatherMovedLeavesFn{tree, arrays});
  exec.for_each_n(leaves, PlaceMovedLeavesFn{tree, arrays});
  // Splits outside the candidates are never touched by the climb; clearing all is cheaper
  // than scattering the clears.
  exec.fill(bvh.other_bound.data(), n - 1, kNoNode);
  exec.fill(bvh.count_log.data(), size_t(n) + 1, 0u);
  exec.for_each_n(leaves, SubtreeClimbFn{apetrei_tree(bvh, bvh.morton.data()), arrays}, Balance::uneven);
  exec.exclusive_scan(bvh.count_log.data(), bvh.offset_log.data(), size_t(n) + 1, bvh.temp.data(),
                      bvh.temp.size());
  const DepthFirstLayout layout = depth_first_layout(bvh);
  exec.for_each_n(leaves, SubtreeLayoutFn{layout, arrays}, Balance::uneven);
  exec.for_each_n(leaves, SubtreePlaceFn{layout, arrays});
  // Node ranges inside the candidates changed: so may which of them span refit tiles.
  index_refit(exec, bvh);
}

}  // namespace cdb
