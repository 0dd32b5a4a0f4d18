#pragma once
// A frame's pairs by query kind, for scenes that declare queries (docs/results-format.md
// pairs_self, pairs_inter): the sink keeps only the pairs a query asks for, so a pair of
// two faces of one object answers a self query and a pair of two objects an inter query.
// Counted on the host from the frame's pairs, after the frame, outside its time.
#include <cstdint>
#include <vector>

#include "cdbench/core/pair.h"
#include "cdbench/geometry/mesh.h"
#include "cdbench/pipeline/pipeline.h"

namespace cdb {

class QueryPairCounter {
 public:
  explicit QueryPairCounter(const Topology& topology);
  // False for a scene without declared queries: its pairs are one count.
  bool active() const { return !face_object_.empty(); }
  QueryPairs count(const std::vector<PrimPair>& pairs) const;

 private:
  std::vector<uint32_t> face_object_;  // per face, its object's index
};

}  // namespace cdb
