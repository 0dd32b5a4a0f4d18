#include "inter_cases.h"
#include "knob_cases.h"

namespace cdb::test {

TEST(HostKnobs, MarginGivesExactlyTheInflatedBoxPairs) {
  auto soup = fast_soup(5);
  check_margin("cpu", *soup, 0.25f * mean_box_extent(*soup));
  auto cloth = rolling_cloth(5);
  check_margin("cpu", *cloth, 0.5f * mean_box_extent(*cloth));
}

TEST(HostKnobs, SweptGivesExactlyTheSweptBoxPairs) {
  auto soup = fast_soup(5);
  check_swept("cpu", *soup);
  auto cloth = rolling_cloth(5);
  check_swept("cpu", *cloth);
}

TEST(HostKnobs, LazyRefitKeepsTheLastRefitsBoxesAndMissesPairs) {
  auto soup = fast_soup(7);
  check_lazy_refit("cpu", *soup, 3);
}

// A scene split into a deformable and a rigid tree (declared queries): both trees keep
// their last refit's boxes between refits, so the pairs are exactly the stale boxes'
// overlaps among the pairs the scene asks for, and the teleporting rigid bodies are missed.
TEST(HostKnobs, LazyRefitOnSplitTreesKeepsBothTreesStale) {
  StoredFrames scene(with_queries(jumping_rigid_bodies(7, false), {"soup"}, {{"soup", "tri"}, {"soup", "box"}}));
  check_lazy_refit("cpu", scene, 3);
}

}  // namespace cdb::test
