#pragma once
// Scenes with deformable and rigid objects and declared queries (docs/design.md
// "Deformable and rigid objects"), written once over the executor: the generators' scenes
// with every combination of queries that selects a different set of trees and traversals,
// and synthetic scenes whose rigid objects jump across the scene between frames (fronts
// sprout and prune far), one with a single-triangle rigid object (T_R is one leaf) and a
// deformable object far from everything. Every pipeline must report the filtered oracle's
// pairs on every frame; failures name the scene (SCOPED_TRACE), pipeline and frame.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "baseline_cases.h"
#include "bvh_cases.h"
#include "cdbench/geometry/object_split.h"

namespace cdb::test {

struct InterCase {
  std::string name;
  std::function<SceneFrames()> make;
  bool deformable_self, cross, rigid_self;  // what the split must find
  // Deformable objects the split puts in T_R (SplitRule::queries: only inters with T_D's
  // self-queried deformable objects name them).
  std::vector<std::string> deformable_in_rigid_tree = {};
  SplitRule rule = SplitRule::rigid;  // --split-objects for the case's pipelines
};

inline void PrintTo(const InterCase& c, std::ostream* os) { *os << c.name; }

inline std::string inter_case_name(const testing::TestParamInfo<InterCase>& info) { return info.param.name; }

inline uint32_t object_named(const Topology& t, const std::string& name) {
  for (uint32_t o = 0; o < t.objects.size(); ++o)
    if (t.objects[o].name == name) return o;
  ADD_FAILURE() << "no object " << name;
  return 0;
}

// Replaces a scene's queries by the named ones.
inline SceneFrames with_queries(SceneFrames s, const std::vector<std::string>& self,
                                const std::vector<std::pair<std::string, std::string>>& inter) {
  ObjectQueries q;
  q.declared = true;
  for (const auto& n : self) q.self.push_back(object_named(s.topology, n));
  for (const auto& [a, b] : inter) q.inter.push_back({object_named(s.topology, a), object_named(s.topology, b)});
  s.topology.queries = q;
  return s;
}

// Every object deformable: rigid bodies that the scene calls deforming (as an avatar is).
inline SceneFrames all_deformable(SceneFrames s) {
  for (SceneObject& o : s.topology.objects) o.rigid = false;
  return s;
}

// Appends an object of the given triangles (3 corners each, per frame).
inline void add_object(SceneFrames& s, const std::string& name, bool rigid,
                       const std::vector<std::vector<vec3f>>& corners_per_frame) {
  const uint32_t first = uint32_t(s.topology.faces.size());
  const uint32_t tris = uint32_t(corners_per_frame.at(0).size() / 3);
  for (uint32_t t = 0; t < tris; ++t) {
    const uint32_t base = s.topology.num_vertices + 3 * t;
    s.topology.faces.push_back({base, base + 1, base + 2});
  }
  s.topology.num_vertices += 3 * tris;
  for (size_t f = 0; f < s.frames.size(); ++f)
    s.frames[f].insert(s.frames[f].end(), corners_per_frame.at(f).begin(), corners_per_frame.at(f).end());
  s.topology.objects.push_back({name, first, tris, rigid});
}

// A jittering clustered soup ("soup", deformable) with, per frame, a rigid triangle ("tri")
// and a rigid box ("box", 12 triangles) teleported to a new place inside or outside the
// soup, and a deformable object ("far", 4 triangles) far from everything. With
// `single_rigid`, only the triangle is rigid: T_R is a single leaf.
inline SceneFrames jumping_rigid_bodies(uint32_t frames, bool single_rigid) {
  SceneFrames s = frames_of(*make_generator("soup", {{"triangles", 1000},
                                                       {"distribution", "clustered"},
                                                       {"jitter", 3.0},
                                                       {"frames", frames},
                                                       {"seed", 23}}));
  s.topology.objects = {{"soup", 0, uint32_t(s.topology.faces.size()), false}};
  Aabb<float> box = Aabb<float>::empty();
  for (const vec3f& p : s.frames[0]) box.grow({p.x, p.y, p.z, 0}, {p.x, p.y, p.z, 0});
  const vec3f lo{box.lo.x, box.lo.y, box.lo.z}, ext{box.hi.x - box.lo.x, box.hi.y - box.lo.y, box.hi.z - box.lo.z};
  // Places in the soup's box (fractions of it) and one far outside, visited in a jumping order.
  const float places[6][3] = {{0.1f, 0.1f, 0.1f}, {0.9f, 0.8f, 0.7f}, {0.5f, 0.5f, 0.5f},
                              {5.0f, -4.0f, 3.0f}, {0.2f, 0.9f, 0.4f}, {0.7f, 0.2f, 0.9f}};
  auto at = [&](uint32_t k) {
    const float* p = places[k % 6];
    return vec3f{lo.x + p[0] * ext.x, lo.y + p[1] * ext.y, lo.z + p[2] * ext.z};
  };
  std::vector<std::vector<vec3f>> tri(frames), cube(frames), far(frames);
  const float r = 0.05f * ext.x;
  for (uint32_t f = 0; f < frames; ++f) {
    const vec3f c = at(2 * f + 1);
    // The triangle turns a quarter each frame (a rigid motion: rotation and translation).
    const bool turned = f % 2 == 1;
    tri[f] = {{c.x - r, c.y, c.z}, turned ? vec3f{c.x, c.y + r, c.z} : vec3f{c.x + r, c.y, c.z},
              {c.x, c.y, c.z + r}};
    SceneFrames box_tris;
    std::vector<vec3f> corners;
    const vec3f b = at(5 * f + 2);
    const float h = 0.12f * ext.x;
    add_cube(box_tris, corners, {b.x - h, b.y - h, b.z - h}, {b.x + h, b.y + h, b.z + h});
    for (const Tri& t : box_tris.topology.faces)
      for (uint32_t v : {t.v0, t.v1, t.v2}) cube[f].push_back(corners[v]);
    const vec3f d{lo.x + 40.0f * ext.x, lo.y, lo.z};
    for (int k = 0; k < 4; ++k) {
      const float o = float(k) * r + 0.01f * float(f) * r;
      far[f].insert(far[f].end(), {{d.x + o, d.y, d.z}, {d.x + o + r, d.y, d.z}, {d.x + o, d.y + r, d.z}});
    }
  }
  add_object(s, "tri", true, tri);
  if (!single_rigid) add_object(s, "box", true, cube);
  add_object(s, "far", false, far);
  return s;
}

inline SceneFrames funnel_frames(uint32_t res, uint32_t frames) {
  return frames_of(*make_generator("funnel", {{"res", res}, {"frames", frames}, {"segments", 16}, {"ball_level", 1}}));
}

// The cases, at a size for the executor (res: cloth resolution, frames per scene).
inline std::vector<InterCase> inter_cases(uint32_t res, uint32_t frames) {
  using Inter = std::vector<std::pair<std::string, std::string>>;
  auto funnel = [res, frames](std::vector<std::string> self, Inter inter) {
    return [=] { return with_queries(funnel_frames(res, frames), self, inter); };
  };
  auto jumps = [frames](bool single, std::vector<std::string> self, Inter inter) {
    return [=] { return with_queries(jumping_rigid_bodies(frames, single), self, inter); };
  };
  auto generated = [res, frames](const char* gen) {
    return [=] {
      return with_queries(frames_of(*make_generator(gen, {{"res", res}, {"frames", frames}})), {"cloth"},
                          {{"cloth", "ball"}});
    };
  };
  return {
      {"funnel_declared", funnel({"cloth"}, {{"cloth", "funnel"}, {"cloth", "ball"}}), true, true, false},
      {"funnel_inter_only", funnel({}, {{"cloth", "funnel"}, {"cloth", "ball"}}), false, true, false},
      {"funnel_self_only", funnel({"cloth"}, {}), true, false, false},
      {"funnel_rigid_rigid", funnel({"cloth"}, {{"cloth", "ball"}, {"funnel", "ball"}}), true, true, true},
      {"funnel_everything",
       funnel({"cloth", "funnel", "ball"}, {{"cloth", "funnel"}, {"cloth", "ball"}, {"funnel", "ball"}}), true,
       true, true},
      {"funnel_rigid_only", funnel({"ball"}, {{"funnel", "ball"}}), false, false, true},
      {"sphere_declared", generated("sphere"), true, true, false},
      {"cloth_ball_declared", generated("cloth-ball"), true, true, false},
      {"jumps_declared",
       jumps(false, {"soup", "far"}, {{"soup", "tri"}, {"soup", "box"}, {"far", "box"}, {"tri", "box"}}), true,
       true, true},
      {"jumps_inter_only", jumps(false, {}, {{"soup", "tri"}, {"soup", "box"}, {"far", "tri"}}), false, true,
       false},
      {"jumps_single_rigid_triangle", jumps(true, {"soup"}, {{"soup", "tri"}, {"far", "tri"}}), true, true, false},
      // The funnel and the ball as deforming colliders: T_R takes them, rebuilt with T_D.
      {"funnel_deforming_colliders",
       [=] { return all_deformable(funnel({"cloth"}, {{"cloth", "funnel"}, {"cloth", "ball"}})()); }, true, true,
       false, {"funnel", "ball"}, SplitRule::queries},
      // The ball deforming, the funnel rigid: T_R holds both kinds.
      {"funnel_deforming_ball",
       [=] {
         SceneFrames s = funnel({"cloth"}, {{"cloth", "ball"}, {"cloth", "funnel"}})();
         s.topology.objects[object_named(s.topology, "ball")].rigid = false;
         return s;
       },
       true, true, false, {"ball"}, SplitRule::queries},
  };
}

// Pipeline c decides from T_D's self fronts (its inspection reads them): the cases with them.
inline std::vector<InterCase> inter_decision_cases(uint32_t res, uint32_t frames) {
  std::vector<InterCase> out;
  for (InterCase& c : inter_cases(res, frames))
    if (c.deformable_self) out.push_back(std::move(c));
  return out;
}

// A tree built with the faces grouped by object (as T_R is): valid, each object's leaves
// contiguous and under one subtree, and its self query exact after refits.
template <class Exec>
void check_grouped_build(FrameSource& source) {
  const Topology& topo = source.topology();
  Exec exec;
  Lbvh<Exec> bvh(exec);
  TestMesh<Exec> m(exec, topo);
  const PairFilterTables tables = pair_filter_tables(topo.objects, {}, topo.faces.size());
  Array<uint32_t> group(exec.memory(), "test.group");
  group.reserve(tables.face_object.size());
  exec.copy_from_host(group.data(), tables.face_object.data(), tables.face_object.size());
  const uint32_t n = uint32_t(topo.faces.size());
  std::vector<vec3f> v;
  for (uint32_t f = 0; f < source.num_frames(); ++f) {
    source.frame(f, v);
    m.upload(exec, v);
    if (f == 0) {
      build_hierarchy(exec, bvh, m.view(), MortonBits::b63, FaceSubset{nullptr, n}, group.data());
      order_depth_first(exec, bvh);
    } else {
      refit(exec, bvh, m.view());
    }
    const HostBvh h = download(exec, bvh);
    ASSERT_EQ(check_bvh(h, topo, v), "") << "frame " << f;
    for (uint32_t i = 1; i < n; ++i)
      ASSERT_LE(tables.face_object[h.leaf_prim[i - 1]], tables.face_object[h.leaf_prim[i]]) << "leaf " << i;
    uint32_t first = 0;
    for (const SceneObject& o : topo.objects) {
      bool subtree = o.num_faces == 1;
      for (uint32_t k = 0; k + 1 < n && !subtree; ++k)
        subtree = h.node_first[k] == first && h.node_last[k] == first + o.num_faces - 1;
      EXPECT_TRUE(subtree) << "object " << o.name << " is not one subtree";
      first += o.num_faces;
    }
    expect_self_query_exact(exec, bvh, topo, v, m.pairs, m.count, f);
    if (testing::Test::HasFatalFailure()) return;
  }
}

// Whether the case's split puts object `o` in T_R.
inline bool in_rigid_tree(const InterCase& c, const SceneObject& o) {
  return o.rigid || std::find(c.deformable_in_rigid_tree.begin(), c.deformable_in_rigid_tree.end(), o.name) !=
                        c.deformable_in_rigid_tree.end();
}

// The split the pipelines take from the scene: traversals as the case expects, every face
// in exactly one tree by its object's kind and queries.
inline void check_split(const InterCase& c) {
  const SceneFrames s = c.make();
  const ObjectSplit split = split_objects(s.topology, c.rule);
  ASSERT_TRUE(split.split);
  EXPECT_EQ(split.deformable_self, c.deformable_self);
  EXPECT_EQ(split.cross, c.cross);
  EXPECT_EQ(split.rigid_self, c.rigid_self);
  std::vector<int> seen(s.topology.faces.size(), 0);
  for (uint32_t f : split.deformable_faces) seen.at(f) += 1;
  for (uint32_t f : split.rigid_faces) seen.at(f) += 2;
  for (const SceneObject& o : s.topology.objects)
    for (uint32_t f = o.first_face; f < o.first_face + o.num_faces; ++f)
      ASSERT_EQ(seen[f], in_rigid_tree(c, o) ? 2 : 1) << "face " << f << " of " << o.name;
  EXPECT_EQ(split.rigid_tree_deforms, !c.deformable_in_rigid_tree.empty());
}

// The pipelines that split a scene: `bvh` and every front pipeline.
inline const std::vector<std::string>& splitting_pipelines() {
  static const std::vector<std::string> names = {"bvh",     "unordered", "static", "periodic", "restructure",
                                                 "reference", "a",       "b",      "c",        "radix-order"};
  return names;
}

// Every splitting pipeline exact on every frame, for front cycles 1 (update every frame)
// and 3 (cycle 2 runs in check_inter_fronts), with buffers far too small at the start, and
// with T_D rebuilt every third frame.
// (The other pipelines only filter, and are checked on declared queries elsewhere.)
inline void check_inter_pipelines(const std::string& device, const InterCase& c) {
  SCOPED_TRACE("scene " + c.name);
  const ExactFrames scene = exact_frames(StoredFrames(c.make()));
  const auto& only = splitting_pipelines();
  for (uint32_t cycle : {1u, 3u}) {
    SCOPED_TRACE("front cycle " + std::to_string(cycle));
    PipelineConfig cfg = config_for(device, 0.5, 0.05, cycle);
    cfg.tree.split = c.rule;
    check_pipelines_on(cfg, scene, 0, only);
    if (testing::Test::HasFatalFailure()) return;
  }
  SCOPED_TRACE("rebuild every 3 frames");
  PipelineConfig cfg = config_for(device, 0.5, 0.05, 2);
  cfg.tree.split = c.rule;
  cfg.tree.rebuild_every = 3;
  check_pipelines_on(cfg, scene, 0, only);
}

// The fronts a split scene keeps, per front pipeline and frame: self fronts of T_D only
// when a D-D query is declared, cross fronts (at least one node per deformable leaf) only
// for a D-R query, T_R self fronts only for an R-R query. T_R is built on the first frame
// and then only refitted (or rebuilt with T_D): once T_D refits too, no frame spends time
// building.
inline void check_inter_fronts(const std::string& device, const InterCase& c) {
  SCOPED_TRACE("scene " + c.name);
  const ExactFrames scene = exact_frames(StoredFrames(c.make()));
  const Topology& topo = scene.topology;
  const uint32_t deformable = uint32_t(split_objects(topo, c.rule).deformable_faces.size());
  for (const std::string name : {"a", "b", "c", "unordered", "static", "periodic", "restructure",
                                 "radix-order", "reference", "bvh"}) {
    SCOPED_TRACE("pipeline " + name);
    PipelineConfig cfg = config_for(device, 8.0, 8.0, 2);
    cfg.name = name;
    cfg.tree.split = c.rule;
    const std::vector<FrameStats> frames = run_exact(cfg, scene);
    ASSERT_EQ(frames.size(), scene.num_frames());
    for (size_t f = 0; f < frames.size(); ++f) {
      const FrameStats& s = frames[f];
      SCOPED_TRACE("frame " + std::to_string(f) + " (" + s.op + ")");
      const bool fronts = name != "bvh";
      EXPECT_EQ(s.fronts.internal + s.fronts.external > 0, fronts && c.deformable_self);
      EXPECT_EQ(s.fronts.inter > 0, fronts && c.cross);
      if (fronts && c.cross) {
        EXPECT_GE(s.fronts.inter, deformable);
      }
      EXPECT_EQ(s.fronts.rigid > 0, fronts && c.rigid_self);
      const double build_ms = s.timing.phase_ms[size_t(Phase::build)];
      if (f == 0) {
        EXPECT_GT(build_ms, 0.0);
      } else if (s.op.rfind("refit", 0) == 0) {
        EXPECT_EQ(build_ms, 0.0) << "a tree was rebuilt on a refit frame";
        EXPECT_GT(s.timing.phase_ms[size_t(Phase::refit)], 0.0);
      }
    }
  }
}

// Pipeline c's Formula 2 forced into each branch on a split scene: restructuring or
// rebuilding T_D renumbers the leaves the cross fronts query, which must regenerate.
inline void check_inter_decisions(const std::string& device, const InterCase& c) {
  SCOPED_TRACE("scene " + c.name);
  const ExactFrames scene = exact_frames(StoredFrames(c.make()));
  for (uint32_t cycle : {1u, 2u}) check_forced_decisions(device, scene, cycle, c.rule);
}

}  // namespace cdb::test
