// Deformable and rigid objects with declared queries on the host executor: the split into
// T_D and T_R, every pipeline exact on every frame, the fronts each query keeps, and
// pipeline c's decisions with cross fronts (tests/inter_cases.h).
#include "error_of.h"
#include "inter_cases.h"
#include "cdbench/exec/host_exec.h"
#include "scenes/load/scene.h"

namespace cdb::test {

class HostInter : public testing::TestWithParam<InterCase> {};

TEST_P(HostInter, SplitFollowsTheDeclaredQueries) { check_split(GetParam()); }

TEST_P(HostInter, AllPipelinesExactEveryFrame) { check_inter_pipelines("cpu", GetParam()); }

TEST_P(HostInter, FrontsFollowTheQueriesAndTheRigidTreeOnlyRefits) { check_inter_fronts("cpu", GetParam()); }

INSTANTIATE_TEST_SUITE_P(Scenes, HostInter, testing::ValuesIn(inter_cases(16, 8)), inter_case_name);

class HostInterDecisions : public testing::TestWithParam<InterCase> {};

TEST_P(HostInterDecisions, EveryBranchOfFormula2IsExact) { check_inter_decisions("cpu", GetParam()); }

INSTANTIATE_TEST_SUITE_P(Scenes, HostInterDecisions, testing::ValuesIn(inter_decision_cases(24, 8)),
                         inter_case_name);

// Without declared queries nothing is split: one tree, every face in it, its self traversal
// only. Nor without rigid objects under --split-objects rigid, or where every deformable
// object is in T_D's queries: one not named by a self query but in an inter with another
// such object (the funnel with the ball, here) stays, and so does its partner.
TEST(HostInter, UnsplitWithoutQueriesOrWithoutObjectsForTheSecondTree) {
  SceneFrames funnel = funnel_frames(12, 1);
  EXPECT_FALSE(split_objects(funnel.topology, SplitRule::queries).split);
  auto expect_unsplit = [](const ObjectSplit& s) {
    EXPECT_FALSE(s.split);
    EXPECT_TRUE(s.deformable_self);
    EXPECT_FALSE(s.cross || s.rigid_self || s.rigid_tree_deforms);
    EXPECT_TRUE(s.deformable_faces.empty() && s.rigid_faces.empty());
  };
  const SceneFrames deformable = all_deformable(with_queries(funnel_frames(12, 1), {"cloth"}, {{"cloth", "ball"}}));
  expect_unsplit(split_objects(deformable.topology, SplitRule::rigid));
  const ObjectSplit by_queries = split_objects(deformable.topology, SplitRule::queries);
  EXPECT_TRUE(by_queries.split && by_queries.cross && by_queries.rigid_tree_deforms);
  const SceneFrames chained =
      all_deformable(with_queries(funnel_frames(12, 1), {"cloth"}, {{"cloth", "ball"}, {"funnel", "ball"}}));
  expect_unsplit(split_objects(chained.topology, SplitRule::queries));
}

TEST(HostInter, SplitRuleNamesRoundTrip) {
  for (SplitRule r : {SplitRule::rigid, SplitRule::queries}) EXPECT_EQ(parse_split_rule(split_rule_name(r)), r);
  EXPECT_NE(error_of([] { parse_split_rule("deformable"); }).find("rigid, queries"), std::string::npos);
}

TEST(HostInter, GroupedBuildGivesEachObjectItsOwnSubtree) {
  for (const char* gen : {"funnel", "cloth-ball"}) {
    SCOPED_TRACE(gen);
    auto scene = make_generator(gen, {{"res", 16}, {"frames", 3}});
    check_grouped_build<HostExec>(*scene);
  }
}

// The shipped scenes with declared queries open, declare what they say, and split.
TEST(HostInter, ShippedInterScenesSplit) {
  for (const char* name : {"funnel-inter", "sphere-inter", "cloth-ball-inter"}) {
    SCOPED_TRACE(name);
    Scene s = open_scene(name, default_scenes_dir(), {{"res", 12}, {"frames", 3}});
    const ObjectSplit split = split_objects(s.source->topology(), SplitRule::rigid);
    EXPECT_TRUE(split.split);
    EXPECT_TRUE(split.deformable_self);
    EXPECT_TRUE(split.cross);
    EXPECT_FALSE(split.rigid_self);
    check_pipelines_on(config_for("cpu", 0.5, 0.05, 2), *s.source);
  }
}

}  // namespace cdb::test
