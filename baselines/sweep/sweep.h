#pragma once
// GPU sort-and-sweep baseline (issue 6). Per frame: triangle boxes; the axis along which
// the box centroids vary most (picked on the device, no host round trip); boxes sorted by
// their minimum along that axis; then one thread per sorted box walks forward while the
// next box's minimum is within its maximum, testing full 3D overlap.
//
// Exact for closed boxes: the sorted minima are non-decreasing as floats, so for an
// overlapping pair (a before b) lo(b) <= hi(a) and every box between them also starts at
// or before hi(a); the walk from a reaches b, and each pair is tested only from the earlier
// of its two boxes.
#include <cstddef>
#include <cstdint>

#include "baselines/common/sorted_boxes.h"
#include "baselines/common/staged_pairs.h"
#include "cdbench/core/aabb.h"
#include "cdbench/core/pair_sink.h"
#include "cdbench/exec/balance.h"
#include "cdbench/exec/gather.h"
#include "cdbench/exec/memory.h"
#include "cdbench/geometry/mesh.h"

namespace cdb {

// Sums and squared sums of the box centroids per axis. Doubles, and shifted by the first
// box's centroid, so that 1e20-scale coordinates neither overflow nor cancel.
struct CentroidMoments {
  double sum[3];
  double sq[3];
};

struct MomentsSum {
  CDB_HD CentroidMoments operator()(const CentroidMoments& a, const CentroidMoments& b) const {
    CentroidMoments r;
    for (int k = 0; k < 3; ++k) {
      r.sum[k] = a.sum[k] + b.sum[k];
      r.sq[k] = a.sq[k] + b.sq[k];
    }
    return r;
  }
};

CDB_HD_INLINE double box_centre(const vec4f& lo, const vec4f& hi, int axis) {
  const float l = axis == 0 ? lo.x : axis == 1 ? lo.y : lo.z;
  const float h = axis == 0 ? hi.x : axis == 1 ? hi.y : hi.z;
  return 0.5 * (double(l) + double(h));
}

struct CentroidMomentsFn {
  const vec4f* lo;
  const vec4f* hi;
  CDB_HD CentroidMoments operator()(uint32_t i) const {
    CentroidMoments m;
    const vec4f a = lo[i], b = hi[i], a0 = lo[0], b0 = hi[0];
    for (int k = 0; k < 3; ++k) {
      const double d = box_centre(a, b, k) - box_centre(a0, b0, k);
      m.sum[k] = d;
      m.sq[k] = d * d;
    }
    return m;
  }
};

// One thread: the axis of largest centroid variance (ties keep the lower axis).
struct PickAxisFn {
  const CentroidMoments* moments;
  uint32_t n;
  uint32_t* axis;
  CDB_HD void operator()(uint32_t) const {
    const CentroidMoments m = *moments;
    uint32_t best = 0;
    double best_var = -1.0;
    for (uint32_t k = 0; k < 3; ++k) {
      const double mean = m.sum[k] / n;
      const double var = m.sq[k] / n - mean * mean;
      if (var > best_var) {
        best_var = var;
        best = k;
      }
    }
    *axis = best;
  }
};

CDB_HD_INLINE float axis_of(const vec4f& v, uint32_t axis) {
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

// The sort's coordinate: along the axis picked on the device.
struct PickedAxis {
  const uint32_t* axis;
  CDB_HD float operator()(const vec4f& v) const { return axis_of(v, *axis); }
};

struct SweepFn : StagedPairs {
  uint32_t n;
  const uint32_t* axis;
  const uint32_t* order;
  const vec4f* lo;  // sorted
  const vec4f* hi;  // sorted
  CDB_HD void operator()(uint32_t s, Stage* stage = nullptr) const {
    const PairSink out = sink.staged(stage);
    const uint32_t ax = *axis;
    const vec4f alo = lo[s], ahi = hi[s];
    const float end = axis_of(ahi, ax);
    for (uint32_t t = s + 1; t < n; ++t) {
      const vec4f blo = lo[t];
      if (axis_of(blo, ax) > end) break;
      if (overlaps(alo, ahi, blo, hi[t])) out.emit(order[s], order[t]);
    }
  }
};

// Workspace of the sweep, sized once from the triangle count; a larger scene later is a
// logged growth.
template <class Exec>
struct SweepAndPrune : SortedBoxes<Exec> {
  explicit SweepAndPrune(Exec& exec) : SortedBoxes<Exec>(exec, "sweep") {
    bind_arrays(exec.memory(), "sweep.",
                {{&sorted_lo, "sorted_lo"}, {&sorted_hi, "sorted_hi"}, {&moments, "moments"}, {&axis, "axis"}});
  }

  void reserve(Exec& exec, uint32_t n) {
    SortedBoxes<Exec>::reserve(exec, n, exec.template reduce_temp_bytes_of<CentroidMoments>(n));
    for (auto* a : {&sorted_lo, &sorted_hi}) a->reserve(n);
    moments.reserve(1);
    axis.reserve(1);
  }

  Array<vec4f> sorted_lo, sorted_hi;
  Array<CentroidMoments> moments;
  Array<uint32_t> axis;
};

template <class Exec>
void sweep_boxes(Exec& exec, SweepAndPrune<Exec>& s, const MeshView& mesh) {
  face_boxes(exec, s, mesh);
}

// Axis choice, keys, sort, gather.
template <class Exec>
void sweep_sort(Exec& exec, SweepAndPrune<Exec>& s, uint32_t n) {
  if (n == 0) return;
  exec.reduce(n, CentroidMomentsFn{s.lo.data(), s.hi.data()}, MomentsSum{}, CentroidMoments{},
              s.moments.data(), s.temp.data(), s.temp.size());
  exec.for_each_n(1, PickAxisFn{s.moments.data(), n, s.axis.data()});
  sort_boxes(exec, s, n, PickedAxis{s.axis.data()});
  gather(exec, n, s.order.data(), s.lo.data(), s.hi.data(), s.sorted_lo.data(), s.sorted_hi.data());
}

template <class Exec>
void sweep_pairs(Exec& exec, const SweepAndPrune<Exec>& s, uint32_t n, const PairSink& sink) {
  exec.for_each_staged(n, SweepFn{{sink}, n, s.axis.data(), s.order.data(), s.sorted_lo.data(),
                             s.sorted_hi.data()},
                  Balance::uneven);
}

}  // namespace cdb
