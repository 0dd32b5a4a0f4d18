#pragma once
// Host-side copies of an ordered LBVH and the plain reference checks the tests run on
// them: structure, boxes, exact depth-first order, escape indices from a recursive DFS.
#include <string>
#include <vector>

#include "cdbench/bvh/lbvh.h"
#include "cdbench/core/pair.h"
#include "cdbench/geometry/mesh.h"

namespace cdb::test {

struct HostBvh {
  uint32_t n = 0;
  std::vector<vec4f> leaf_lo, leaf_hi, node_lo, node_hi;
  std::vector<uint32_t> leaf_prim, leaf_parent, leaf_escape;
  std::vector<uint32_t> node_left, node_right, node_parent, node_escape, node_first, node_last;
  std::vector<uint32_t> count_log, offset_log;
};

template <class Exec, class T>
std::vector<T> download(Exec& exec, const Array<T>& a, size_t n) {
  std::vector<T> out(n);
  exec.copy_to_host(out.data(), a.data(), n);
  return out;
}

// The tree's boxes (bvh/node_box.h) as the two corners' arrays the checks read.
template <class Exec>
void download_boxes(Exec& exec, const Array<NodeBox>& a, size_t n, std::vector<vec4f>& lo, std::vector<vec4f>& hi) {
  const std::vector<NodeBox> boxes = download(exec, a, n);
  lo.resize(n);
  hi.resize(n);
  for (size_t k = 0; k < n; ++k) lo[k] = boxes[k].lo, hi[k] = boxes[k].hi;
}

template <class Exec>
HostBvh download(Exec& exec, const Lbvh<Exec>& b) {
  HostBvh h;
  h.n = b.num_leaves;
  const size_t n = h.n, m = n > 1 ? n - 1 : 0;
  download_boxes(exec, b.leaf_box, n, h.leaf_lo, h.leaf_hi);
  h.leaf_prim = download(exec, b.leaf_prim, n);
  h.leaf_parent = download(exec, b.leaf_parent, n);
  h.leaf_escape = download(exec, b.leaf_escape, n);
  download_boxes(exec, b.node_box, m, h.node_lo, h.node_hi);
  h.node_left = download(exec, b.node_left, m);
  h.node_right = download(exec, b.node_right, m);
  h.node_parent = download(exec, b.node_parent, m);
  h.node_escape = download(exec, b.node_escape, m);
  h.node_first = download(exec, b.node_first, m);
  h.node_last = download(exec, b.node_last, m);
  if (n > 1) {
    h.count_log = download(exec, b.count_log, n + 1);
    h.offset_log = download(exec, b.offset_log, n + 1);
  }
  return h;
}

// Returns an empty string when the tree is valid for these triangles, else what is wrong.
std::string check_bvh(const HostBvh& h, const Topology& topology, const std::vector<vec3f>& vertices);

}  // namespace cdb::test
