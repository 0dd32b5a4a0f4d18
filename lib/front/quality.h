#pragma once
// Quality inspection (paper §4.1). Formula 1: for internal node i covering leaves [s, t],
//   Q(i) = (internal front nodes whose node lies in subtree i)
//        / (external front nodes whose leaf lies in [s, t]),
// each a difference of two entries of the fronts' offset logs, because the depth-first
// layout makes subtree i's internal nodes the contiguous range [i, i + t - s - 1]. Q is
// about the number of internal front nodes it takes per leaf-level test, so it rises when
// the subtree's boxes have degenerated and its fronts sprout.
//
// A node is degraded when Q(i) exceeds `degraded_above` (the run's quality factor times Q
// of the root right after the last rebuild: the quality the builder delivers). Candidates
// for restructuring are the topmost degraded nodes whose size is within [min_leaves,
// max_leaves]: disjoint subtrees, so they can be restructured together.
#include <cstdint>

#include "cdbench/bvh/node_ref.h"
#include "cdbench/core/atomics.h"
#include "cdbench/core/hd.h"

namespace cdb {

// What the inspection counts: degraded candidate subtrees, their leaves, the sum of their Q
// in thousandths (for the recorded mean), and the front nodes in them (internal nodes of
// the subtree, external ones on its leaves: at most what restructuring them can remove,
// pipeline/restructure_price.h).
struct InspectCounters {
  unsigned long long candidates, candidate_leaves, candidate_q_milli, candidate_front_nodes;
};

struct InspectQualityFn {
  const uint32_t* node_first;
  const uint32_t* node_last;
  const uint32_t* node_parent;
  const uint32_t* internal_offset;  // offset log of the internal front (by internal node)
  const uint32_t* external_offset;  // offset log of the external front (by leaf)
  float degraded_above;
  uint32_t min_leaves, max_leaves;
  uint32_t max_candidates;
  uint32_t* candidate_node;
  InspectCounters* counters;

  CDB_HD_INLINE uint32_t leaves_of(uint32_t i) const { return node_last[i] - node_first[i] + 1; }

  // The internal front nodes whose node lies in subtree i, and the external ones whose leaf does.
  CDB_HD_INLINE uint32_t internal_under(uint32_t i) const {
    return internal_offset[i + (node_last[i] - node_first[i])] - internal_offset[i];
  }
  CDB_HD_INLINE uint32_t external_under(uint32_t i) const {
    return external_offset[node_last[i] + 1] - external_offset[node_first[i]];
  }
  // Q(i) of Formula 1; false when no external front node lies under i (no leaf tests: the
  // subtree takes part in no collision and its quality does not matter).
  CDB_HD_INLINE bool quality(uint32_t i, float& q) const {
    const uint32_t internal = internal_under(i);
    const uint32_t external = external_under(i);
    if (external == 0) return false;
    q = float(internal) / float(external);
    return true;
  }

  CDB_HD_INLINE bool in_range(uint32_t i) const {
    const uint32_t leaves = leaves_of(i);
    return leaves >= min_leaves && leaves <= max_leaves;
  }

  CDB_HD_INLINE bool degraded(uint32_t i, float& q) const {
    return in_range(i) && quality(i, q) && q > degraded_above;
  }

  CDB_HD void operator()(uint32_t i) const {
    float q = 0.0f;
    if (!degraded(i, q)) return;
    for (uint32_t p = node_parent[i]; p != kNoNode && leaves_of(p) <= max_leaves; p = node_parent[p]) {
      float qp;
      if (degraded(p, qp)) return;
    }
    const unsigned long long slot = atomic_add_relaxed(&counters->candidates, 1ull);
    if (slot >= max_candidates) return;  // cannot happen: candidates are disjoint
    candidate_node[slot] = i;
    atomic_add_relaxed(&counters->candidate_leaves, static_cast<unsigned long long>(leaves_of(i)));
    atomic_add_relaxed(&counters->candidate_q_milli, static_cast<unsigned long long>(q * 1000.0f));
    atomic_add_relaxed(&counters->candidate_front_nodes,
                       static_cast<unsigned long long>(internal_under(i)) + external_under(i));
  }
};

}  // namespace cdb
