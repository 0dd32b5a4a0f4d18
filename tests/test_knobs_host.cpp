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

}  // namespace cdb::test
