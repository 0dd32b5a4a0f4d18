#pragma once
// Scenes float32 cannot hold (docs/design.md "Box precision"): a folding sheet with
// millimetre edges placed 1e4 to 1e12 from the origin, in double, through every pipeline,
// against the O(N^2) overlaps of the double geometry. test_knobs_host.cpp runs them on the
// host executor, test_bvh_cuda.cu on CUDA.
// - fp64 misses no pair of the double geometry and adds at most 1% (with and without a
//   margin); fp32 misses none either (rounding keeps every overlap) but blurs the sheet far
//   out, which the float-spacing warning predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cdbench/core/error.h"
#include "cdbench/core/pair_set.h"
#include "scenes/generators/generators.h"
#include "cdbench/geometry/float_spacing.h"
#include "cdbench/geometry/position_rounding.h"
#include "scenes/load/placed_scene.h"
#include "cdbench/pipeline/pipeline.h"
#include "registry/pipeline_kinds.h"

namespace cdb::test {

inline constexpr double kMillimetre = 1e-3;

// A 24x24 cloth wave (its edge rolls over the sheet: folds and touching layers), scaled so
// that its median edge is one millimetre, then moved by `offset` on every axis.
inline std::unique_ptr<FrameSource> millimetre_sheet(double offset) {
  auto sheet = make_generator("cloth-wave", {{"res", 24}, {"frames", 2}});
  std::vector<vec3d> p;
  sheet->positions(0, p);
  const double edge = float_spacing(sheet->topology(), p, {0, 0, 0}).median_edge;
  Placement place;
  place.scale = kMillimetre / edge;
  place.offset = {offset, offset, offset};
  return place_scene(std::move(sheet), place);
}

// The pairs of the double geometry's boxes, each grown by `margin` on every side in double:
// plain O(N^2), independent of the pipelines' boxes.
inline std::vector<PrimPair> double_overlaps(const Topology& t, const std::vector<vec3d>& v, double margin) {
  const size_t n = t.faces.size();
  std::vector<vec4d> lo(n), hi(n);
  for (size_t f = 0; f < n; ++f) {
    triangle_box(v[t.faces[f].v0], v[t.faces[f].v1], v[t.faces[f].v2], lo[f], hi[f]);
    lo[f] = {lo[f].x - margin, lo[f].y - margin, lo[f].z - margin, 0};
    hi[f] = {hi[f].x + margin, hi[f].y + margin, hi[f].z + margin, 0};
  }
  std::vector<PrimPair> pairs;
  for (uint32_t i = 0; i < n; ++i)
    for (uint32_t j = i + 1; j < n; ++j)
      if (lo[i].x <= hi[j].x && lo[j].x <= hi[i].x && lo[i].y <= hi[j].y && lo[j].y <= hi[i].y &&
          lo[i].z <= hi[j].z && lo[j].z <= hi[i].z)
        pairs.push_back(make_pair_ordered(i, j));
  return pairs;
}

struct OffsetCase {
  double offset;
};

inline std::string offset_case_name(const testing::TestParamInfo<OffsetCase>& info) {
  return "offset_1e" + std::to_string(int(std::lround(std::log10(info.param.offset))));
}

inline std::vector<OffsetCase> offset_cases() { return {{1e4}, {1e6}, {1e8}, {1e10}, {1e12}}; }

struct DoubleCheck {
  uint64_t pairs = 0, missed = 0, extra = 0;
};

// Every pipeline (brute force included) over the sheet's frames with this precision and
// margin, against the double overlaps; fails on any missed pair.
inline DoubleCheck check_against_double(const std::string& device, double offset, BoxPrecision precision,
                                        float margin) {
  const auto sheet = millimetre_sheet(offset);
  const Topology& topo = sheet->topology();
  std::vector<std::vector<vec3d>> frames(sheet->num_frames());
  std::vector<std::vector<PrimPair>> expected(frames.size());
  for (uint32_t f = 0; f < frames.size(); ++f) {
    sheet->positions(f, frames[f]);
    expected[f] = double_overlaps(topo, frames[f], margin);
  }
  DoubleCheck worst;
  for (const std::string& name : pipeline_names()) {
    PipelineConfig c;
    c.name = name;
    c.device = device;
    c.boxes.precision = precision;
    c.boxes.margin = margin;
    c.fronts.cycle = 1;  // every frame after the first updates its fronts
    const auto p = make_pipeline(c);
    p->set_topology(topo);
    DoubleCheck d;
    for (uint32_t f = 0; f < frames.size(); ++f) {
      p->run_frame(frames[f]);
      const PairSetDiff diff = diff_pair_sets(expected[f], p->sorted_pairs(), 0);
      d.pairs += expected[f].size();
      d.missed += diff.missing_count;
      d.extra += diff.unexpected_count;
    }
    EXPECT_EQ(d.missed, 0u) << name << " " << box_precision_name(precision) << " margin " << margin << ": "
                            << d.missed << " of " << d.pairs << " pairs of the double geometry missed";
    EXPECT_GT(d.pairs, 0u);
    if (d.extra > worst.extra) worst = d;
    worst.pairs = d.pairs;
  }
  return worst;
}

// fp64: nothing missed, at most 1% extra, at every offset.
inline void check_fp64_offset(const std::string& device, double offset) {
  for (float margin : {0.0f, float(kMillimetre / 4)}) {
    const DoubleCheck d = check_against_double(device, offset, BoxPrecision::fp64, margin);
    EXPECT_LE(double(d.extra), 0.01 * double(d.pairs))
        << "offset " << offset << " margin " << margin << ": " << d.extra << " extra pairs over " << d.pairs;
  }
}

// fp32: nothing missed either, but from 1e6 on (float spacing 1/16 there, more than the
// sheet is wide) the sheet blurs into many times its pairs; the spacing check warns from
// 1e4 on (spacing about one edge) and not for fp64, which rebases.
inline void check_fp32_offset(const std::string& device, double offset) {
  const DoubleCheck d = check_against_double(device, offset, BoxPrecision::fp32, 0.0f);
  const auto sheet = millimetre_sheet(offset);
  EXPECT_FALSE(float_spacing_warning(*sheet, 0, false).empty()) << "offset " << offset;
  EXPECT_TRUE(float_spacing_warning(*sheet, 0, true).empty()) << "offset " << offset;
  if (offset >= 1e6) {
    EXPECT_GT(d.extra, d.pairs) << "offset " << offset;
  }
}

}  // namespace cdb::test
