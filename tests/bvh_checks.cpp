#include "bvh_checks.h"

#include <functional>
#include <sstream>

#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/aabb.h"

namespace cdb::test {

namespace {
bool same_box(const vec4f& a, const vec4f& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }
}  // namespace

std::string check_bvh(const HostBvh& h, const Topology& topology, const std::vector<vec3f>& vertices) {
  std::ostringstream err;
  const uint32_t n = h.n;
  if (n != topology.faces.size()) return "leaf count differs from triangle count";
  if (n == 0) return "";
  // Every triangle is exactly one leaf, with its exact box.
  std::vector<int> seen(n, 0);
  for (uint32_t i = 0; i < n; ++i) {
    if (h.leaf_prim[i] >= n) return "leaf_prim out of range";
    ++seen[h.leaf_prim[i]];
    vec4f lo, hi;
    const Tri t = topology.faces[h.leaf_prim[i]];
    triangle_box(vertices[t.v0], vertices[t.v1], vertices[t.v2], lo, hi);
    if (!same_box(lo, h.leaf_lo[i]) || !same_box(hi, h.leaf_hi[i])) {
      err << "leaf " << i << " box differs from its triangle's";
      return err.str();
    }
    // The box's spare lanes carry the escape index and the primitive (bvh/node_ref.h).
    if (lane_link(h.leaf_lo[i].w) != h.leaf_escape[i] || lane_link(h.leaf_hi[i].w) != h.leaf_prim[i]) {
      err << "link lanes of leaf " << i << " differ from its escape index and primitive";
      return err.str();
    }
  }
  for (uint32_t p = 0; p < n; ++p)
    if (seen[p] != 1) {
      err << "triangle " << p << " appears in " << seen[p] << " leaves";
      return err.str();
    }
  if (n == 1) return h.leaf_escape[0] == kNoNode && h.leaf_parent[0] == kNoNode ? "" : "single leaf links wrong";

  // Recursive reference traversal from the root (node 0): preorder of all nodes, subtree
  // ranges, parent links, boxes containing children.
  const uint32_t m = n - 1;
  std::vector<uint32_t> preorder;  // refs
  std::vector<int> child_count_int(m, 0), child_count_leaf(n, 0);
  std::string problem;
  std::function<void(uint32_t, uint32_t, uint32_t&, uint32_t&)> visit =
      [&](uint32_t ref, uint32_t parent, uint32_t& first, uint32_t& last) {
        if (!problem.empty()) return;
        preorder.push_back(ref);
        if (is_leaf(ref)) {
          const uint32_t i = ref_index(ref);
          if (i >= n) { problem = "leaf ref out of range"; return; }
          ++child_count_leaf[i];
          if (h.leaf_parent[i] != parent) problem = "leaf parent link wrong at leaf " + std::to_string(i);
          first = last = i;
          return;
        }
        if (ref >= m) { problem = "internal ref out of range"; return; }
        ++child_count_int[ref];
        if (child_count_int[ref] > 1) { problem = "internal node reached twice: cycle"; return; }
        if (h.node_parent[ref] != parent) problem = "node parent link wrong at node " + std::to_string(ref);
        uint32_t lf, ll, rf, rl;
        const uint32_t l = h.node_left[ref], r = h.node_right[ref];
        visit(l, ref, lf, ll);
        visit(r, ref, rf, rl);
        if (!problem.empty()) return;
        if (ll + 1 != rf) problem = "children ranges not adjacent at node " + std::to_string(ref);
        first = lf;
        last = rl;
        if (h.node_first[ref] != first || h.node_last[ref] != last)
          problem = "node range wrong at node " + std::to_string(ref);
        for (uint32_t c : {l, r}) {
          const vec4f clo = is_leaf(c) ? h.leaf_lo[ref_index(c)] : h.node_lo[c];
          const vec4f chi = is_leaf(c) ? h.leaf_hi[ref_index(c)] : h.node_hi[c];
          if (!contains(h.node_lo[ref], h.node_hi[ref], clo, chi))
            problem = "box of node " + std::to_string(ref) + " does not contain its child";
        }
        // The node box is exactly the union of its children (build and refit both merge).
        Aabb<float> u = Aabb<float>::empty();
        for (uint32_t c : {l, r})
          u.grow(is_leaf(c) ? h.leaf_lo[ref_index(c)] : h.node_lo[c],
                 is_leaf(c) ? h.leaf_hi[ref_index(c)] : h.node_hi[c]);
        if (!same_box(u.lo, h.node_lo[ref]) || !same_box(u.hi, h.node_hi[ref]))
          problem = "box of node " + std::to_string(ref) + " is not the union of its children";
        // The box's spare lanes carry the left and escape links (bvh/node_ref.h).
        if (lane_link(h.node_lo[ref].w) != h.node_left[ref] || lane_link(h.node_hi[ref].w) != h.node_escape[ref])
          problem = "link lanes of node " + std::to_string(ref) + " differ from its links";
      };
  uint32_t f, l;
  if (h.node_parent[0] != kNoNode) return "root (node 0) has a parent";
  visit(0, kNoNode, f, l);
  if (!problem.empty()) return problem;
  if (f != 0 || l != n - 1) return "root does not cover all leaves";
  if (preorder.size() != 2 * size_t(n) - 1) return "traversal did not reach every node";
  for (uint32_t i = 0; i < n; ++i)
    if (child_count_leaf[i] != 1) return "leaf " + std::to_string(i) + " is not a child exactly once";
  // Leaves in traversal order are 0..n-1 and internal nodes are numbered in preorder.
  uint32_t next_leaf = 0, next_node = 0;
  for (uint32_t ref : preorder) {
    if (is_leaf(ref)) {
      if (ref_index(ref) != next_leaf++) return "leaves not in left-to-right order";
    } else if (ref != next_node++) {
      err << "internal nodes not in depth-first order: found " << ref << " at position " << next_node - 1;
      return err.str();
    }
  }
  // Escape index of every node = the node after its subtree in the reference preorder.
  std::vector<size_t> pos_leaf(n), pos_node(m), size_leaf(n, 1), size_node(m);
  for (size_t p = 0; p < preorder.size(); ++p)
    (is_leaf(preorder[p]) ? pos_leaf[ref_index(preorder[p])] : pos_node[preorder[p]]) = p;
  for (uint32_t k = 0; k < m; ++k) size_node[k] = 2 * size_t(h.node_last[k] - h.node_first[k]) + 1;
  auto expected_escape = [&](size_t pos, size_t size) {
    return pos + size < preorder.size() ? preorder[pos + size] : kNoNode;
  };
  for (uint32_t i = 0; i < n; ++i)
    if (h.leaf_escape[i] != expected_escape(pos_leaf[i], 1)) return "escape index wrong at leaf " + std::to_string(i);
  for (uint32_t k = 0; k < m; ++k)
    if (h.node_escape[k] != expected_escape(pos_node[k], size_node[k]))
      return "escape index wrong at node " + std::to_string(k);
  // Order log: count_log[l] internal nodes have leftmost leaf l; offset_log is its scan.
  // It is the build's; a caller that restructured subtrees since clears it.
  if (h.count_log.empty()) return "";
  std::vector<uint32_t> lcl(n + 1, 0);
  for (uint32_t k = 0; k < m; ++k) ++lcl[h.node_first[k]];
  uint32_t sum = 0;
  for (uint32_t i = 0; i <= n; ++i) {
    if (h.count_log[i] != lcl[i]) return "count log wrong at leaf " + std::to_string(i);
    if (h.offset_log[i] != sum) return "offset log wrong at leaf " + std::to_string(i);
    sum += lcl[i];
  }
  return "";
}

}  // namespace cdb::test
