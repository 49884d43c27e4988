#include "core/lane/solved_attitudes.hpp"

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

// Pose `pose` solved to this pitch and yaw, in degrees.
void solved(SolvedAttitudes<16>& at, int pose, double theta_deg, double psi_deg) {
  at.add(pose, deg_to_rad(theta_deg), deg_to_rad(psi_deg));
}

// Twenty poses of a still's search solved to the camera's attitude, within a few tenths of
// a degree, and one fell into a hollow of clutter 12 degrees away (TuSimple still 40 at
// light x0.97 took such a lane, the camera looking 5.6 degrees up): that one is lone, the
// others are not, and a pose that did not solve is neither.
TEST(SolvedAttitudes, ASolveThatOneStartReachedWhereManyReachedAnotherIsLone) {
  SolvedAttitudes<16> at;
  for (int p = 0; p < 12; ++p) solved(at, p, 7.0 + 0.02 * p, 1.4 - 0.03 * p);
  solved(at, 12, -5.6, -13.1);
  EXPECT_EQ(at.sharing(12), 1);
  EXPECT_TRUE(at.lone(12));
  EXPECT_EQ(at.sharing(3), 12);
  EXPECT_FALSE(at.lone(3));
  EXPECT_EQ(at.sharing(13), 0);
  EXPECT_FALSE(at.lone(13));
}

// Half as many as the most is not lone: the development stills' own lanes were reached
// from as few as two starting poses of four. Fewer than half is.
// (Asked as each pose more solves, the answer is the poses' so far.)
TEST(SolvedAttitudes, ASolveReachedFromHalfAsManyAsTheMostIsNotLone) {
  SolvedAttitudes<16> at;
  solved(at, 0, 7.0, 1.0);
  solved(at, 1, 7.1, 1.1);
  for (int others = 1; others <= 5; ++others) {
    solved(at, 1 + others, 9.0, 1.0);
    EXPECT_EQ(at.lone(0), 2 * 2 < others) << others << " others";
  }
}

// The same attitude is within a degree in pitch and in yaw both: a pose a degree and a
// half off in yaw alone, or in pitch alone, reached another.
TEST(SolvedAttitudes, TheSameAttitudeIsWithinADegreeInPitchAndInYaw) {
  SolvedAttitudes<16> at;
  solved(at, 0, 7.0, 1.0);
  solved(at, 1, 7.9, 0.1);
  solved(at, 2, 7.0, 2.5);
  solved(at, 3, 5.5, 1.0);
  EXPECT_EQ(at.sharing(0), 2);
  EXPECT_EQ(at.sharing(2), 1);
  EXPECT_EQ(at.sharing(3), 1);
}

}  // namespace
}  // namespace ccdlane
