#include "core/lane/searched_lanes.hpp"

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

// One picture's lines, at the car, as a camera 1.65 m up sees them: the own lane's at
// +-1.85 m, the next lane's right line at -5.55 m. A search's pose that looked from
// another height has them all in proportion to its height.
constexpr double kTrueHeightMm = 1650.0;
OwnLanePlace seen_from(double height_mm, double left_mm, double right_mm) {
  const double scale = height_mm / kTrueHeightMm;
  return {left_mm * scale, right_mm * scale, height_mm};
}

TEST(SearchedLanes, ALaneThatAnotherPoseShowsToBeTwoLanesYieldsToThatPosesLane) {
  SearchedLanes<8> lanes;
  lanes.add(0, seen_from(825.0, 1850.0, -5550.0), false);   // the own left and the next right line
  lanes.add(3, seen_from(1600.0, 1850.0, -1850.0), false);  // the own lane
  EXPECT_TRUE(lanes.two_lanes(0));
  EXPECT_FALSE(lanes.two_lanes(3));
  EXPECT_EQ(lanes.narrower_than(0), 3);
  EXPECT_FALSE(lanes.as_looked_from(3));
  // The own lane seen again from its own height changes nothing: one lane, at any scale.
  lanes.add(5, seen_from(1650.0, 1850.0, -1850.0), true);
  EXPECT_FALSE(lanes.two_lanes(5));
  EXPECT_EQ(lanes.narrower_than(0), 3);  // the first that shows it
}

TEST(SearchedLanes, ALaneThatIsItselfTwoLanesIsNotTheOneTaken) {
  SearchedLanes<8> lanes;
  lanes.add(0, seen_from(825.0, 1850.0, -5550.0), true);   // two lanes
  lanes.add(1, seen_from(1100.0, 1850.0, -3300.0), true);  // between: the own lane's right line inside it
  lanes.add(2, seen_from(1600.0, 1850.0, -1850.0), false);
  EXPECT_TRUE(lanes.two_lanes(1));
  EXPECT_EQ(lanes.narrower_than(0), 2);
  EXPECT_EQ(lanes.narrower_than(1), 2);
  EXPECT_EQ(lanes.narrower_than(2), -1);
}

TEST(SearchedLanes, WithoutAnotherLaneNothingIsShown) {
  SearchedLanes<4> lanes;
  EXPECT_FALSE(lanes.two_lanes(0));
  EXPECT_EQ(lanes.narrower_than(0), -1);
  lanes.add(1, seen_from(825.0, 1850.0, -5550.0), true);
  EXPECT_FALSE(lanes.two_lanes(1));
  EXPECT_EQ(lanes.narrower_than(1), -1);
  // Poses outside the search's are not recorded, nor asked about.
  lanes.add(7, seen_from(1600.0, 1850.0, -1850.0), false);
  EXPECT_FALSE(lanes.two_lanes(1));
  EXPECT_FALSE(lanes.as_looked_from(-1));
  EXPECT_FALSE(lanes.two_lanes(9));
}

// The search's ranking of its poses' lanes. 100 own-lane picks so far: a count's spread
// is 10 of them.
TEST(SearchedLanes, ALaneWithMoreOwnPicksThanACountsSpreadRanksAboveWhateverElse) {
  const LaneRank taken{100, 4, 0.5};
  EXPECT_TRUE(ranks_above({111, 2, 0.9}, taken, 100));
  EXPECT_FALSE(ranks_above({110, 2, 0.2}, taken, 100));    // within the spread: fewer lines
  EXPECT_FALSE(ranks_above({89, 5, 0.2}, taken, 100));     // fewer picks by more than it
  EXPECT_TRUE(ranks_above({1, 0, 9.0}, std::nullopt, 0));  // the first lane
}

TEST(SearchedLanes, WithinACountsSpreadTheLaneWithMoreOfTheRoadsLinesRanksAbove) {
  const LaneRank taken{100, 2, 0.4};
  EXPECT_TRUE(ranks_above({92, 3, 0.6}, taken, 100));  // fewer picks, a worse fit: more lines
  EXPECT_FALSE(ranks_above({108, 1, 0.3}, taken, 100));
  // The most picks so far set the spread, not the taken lane's own.
  EXPECT_FALSE(ranks_above({92, 3, 0.6}, LaneRank{92, 2, 0.4}, 120));
}

TEST(SearchedLanes, WithAsManyLinesTheBetterFitRanksAboveByMoreThanItsOwnSpread) {
  // An rms's spread over 100 picks is 1 / sqrt(200) of it: 0.035 px of 0.5.
  const LaneRank taken{100, 3, 0.5};
  EXPECT_TRUE(ranks_above({95, 3, 0.46}, taken, 100));
  EXPECT_FALSE(ranks_above({105, 3, 0.47}, taken, 100));
  EXPECT_FALSE(ranks_above({100, 3, 0.5}, taken, 100));  // the same: the first stays
}

}  // namespace
}  // namespace ccdlane
