#pragma once
#include <limits>

#include "cdbench/core/hd.h"
#include "cdbench/core/vec.h"

namespace cdb {

// Axis-aligned box with closed bounds: boxes that only touch overlap (DESIGN §4).
template <class T>
struct Aabb {
  vec4<T> lo, hi;

  CDB_HD_INLINE static Aabb empty() {
    const T inf = std::numeric_limits<T>::infinity();
    return {{inf, inf, inf, 0}, {-inf, -inf, -inf, 0}};
  }
  CDB_HD_INLINE void grow(const vec4<T>& p) { grow(p, p); }
  CDB_HD_INLINE void grow(const vec4<T>& l, const vec4<T>& h) {
    lo.x = min_of(lo.x, l.x); lo.y = min_of(lo.y, l.y); lo.z = min_of(lo.z, l.z);
    hi.x = max_of(hi.x, h.x); hi.y = max_of(hi.y, h.y); hi.z = max_of(hi.z, h.z);
  }
  CDB_HD_INLINE void grow(const Aabb& b) { grow(b.lo, b.hi); }
};

template <class T>
CDB_HD_INLINE bool overlaps(const vec4<T>& alo, const vec4<T>& ahi, const vec4<T>& blo,
                            const vec4<T>& bhi) {
  return alo.x <= bhi.x && blo.x <= ahi.x && alo.y <= bhi.y && blo.y <= ahi.y &&
         alo.z <= bhi.z && blo.z <= ahi.z;
}

template <class T>
CDB_HD_INLINE bool contains(const vec4<T>& olo, const vec4<T>& ohi, const vec4<T>& ilo,
                            const vec4<T>& ihi) {
  return olo.x <= ilo.x && olo.y <= ilo.y && olo.z <= ilo.z && ihi.x <= ohi.x &&
         ihi.y <= ohi.y && ihi.z <= ohi.z;
}

// Box of a triangle: exact (min/max only, no rounding).
template <class T>
CDB_HD_INLINE void triangle_box(const vec3<T>& a, const vec3<T>& b, const vec3<T>& c,
                                vec4<T>& lo, vec4<T>& hi) {
  lo = {min_of(min_of(a.x, b.x), c.x), min_of(min_of(a.y, b.y), c.y),
        min_of(min_of(a.z, b.z), c.z), T(0)};
  hi = {max_of(max_of(a.x, b.x), c.x), max_of(max_of(a.y, b.y), c.y),
        max_of(max_of(a.z, b.z), c.z), T(0)};
}

}  // namespace cdb
