#pragma once
// One step of the stackless depth-first traversal by escape indices (paper Alg. 1, lines
// 1-11) against a query box: where it goes next, and what it met. A step loads the node's
// links (and a leaf's primitive) together with its box, before the overlap test picks one:
// the loads are in flight at once, so a step costs one memory round trip, where loading the
// chosen link after the test cost two, and a hit's pair needs no further load. The links
// and a leaf's primitive come in the box's spare lanes (node_ref.h).
#include <cstdint>

#include "bvh/bvh_view.h"
#include "bvh/node_ref.h"
#include "core/aabb.h"

namespace cdb {

struct NextNode {
  uint32_t next;    // the left child of an internal node that overlaps, else the escape index
  uint32_t escape;  // the escape index: where the node's subtree ends
  uint32_t prim;    // a leaf's primitive
  bool leaf_hit;    // a leaf that overlaps: a pair
  bool stop;        // a leaf, or an internal node that misses: where a front records a node
};

CDB_HD_INLINE NextNode next_node(const BvhView& bvh, uint32_t node, const vec4f& lo, const vec4f& hi) {
  const uint32_t k = ref_index(node);
  if (is_leaf(node)) {
    const vec4f llo = bvh.leaf_lo[k], lhi = bvh.leaf_hi[k];
    const uint32_t escape = lane_link(llo.w);
    return {escape, escape, lane_link(lhi.w), overlaps(lo, hi, llo, lhi), true};
  }
  // The links ride in the box's spare lanes (node_ref.h): two loads from one 32-byte
  // sector pair where four arrays took four lines.
  const vec4f nlo = bvh.node_lo[k], nhi = bvh.node_hi[k];
  const bool hit = overlaps(lo, hi, nlo, nhi);
  const uint32_t escape = lane_link(nhi.w);
  return {hit ? lane_link(nlo.w) : escape, escape, 0u, false, !hit};
}

}  // namespace cdb
