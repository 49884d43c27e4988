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

}  // namespace
}  // namespace ccdlane
