#include "harness/measure/query_pairs.h"

#include "cdbench/geometry/objects.h"

namespace cdb {

QueryPairCounter::QueryPairCounter(const Topology& topology) {
  if (topology.queries.declared)
    face_object_ = pair_filter_tables(topology.objects, topology.queries, topology.faces.size()).face_object;
}

QueryPairs QueryPairCounter::count(const std::vector<PrimPair>& pairs) const {
  QueryPairs q;
  for (const PrimPair& p : pairs) {
    if (face_object_[p.a] == face_object_[p.b])
      ++q.self;
    else
      ++q.inter;
  }
  return q;
}

}  // namespace cdb
