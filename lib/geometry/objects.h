#pragma once
// Objects of a scene and the queries it declares (issue: inter-object CD). Faces are
// numbered across objects in scene order; an object is a contiguous face range, deformable
// or rigid. A scene that declares no queries asks for every overlapping pair (self-CD of
// the whole triangle set); one that does gets only pairs within objects it names under
// "self" and between the object pairs it names under "inter".
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cdbench/core/hd.h"

namespace cdb {

struct SceneObject {
  std::string name;
  uint32_t first_face = 0, num_faces = 0;
  bool rigid = false;
};

struct ObjectQueries {
  bool declared = false;                               // false: every pair
  std::vector<uint32_t> self;                          // object indices
  std::vector<std::pair<uint32_t, uint32_t>> inter;    // object index pairs
};

// The largest number of objects a scene with declared queries may have: partners are a
// 64-bit mask per object.
inline constexpr size_t kMaxQueryObjects = 64;

// Per face, its object's index; per object, the bit mask of objects it is queried against
// (its own bit when self is declared). Faces outside every object get kMaxQueryObjects - 1
// only if the objects leave gaps, which scene validation forbids.
struct PairFilterTables {
  std::vector<uint32_t> face_object;
  std::vector<uint64_t> partners;
};

// Throws cdb::Error when objects overlap, leave faces uncovered, exceed kMaxQueryObjects, or
// a query names an object index out of range.
PairFilterTables pair_filter_tables(const std::vector<SceneObject>& objects, const ObjectQueries& q,
                                    size_t num_faces);

// Whether faces i and j (of objects oi and oj) are a pair the scene asks for.
CDB_HD_INLINE bool pair_wanted(const uint32_t* face_object, const uint64_t* partners, uint32_t i,
                               uint32_t j) {
  return (partners[face_object[i]] >> face_object[j]) & 1u;
}

}  // namespace cdb
