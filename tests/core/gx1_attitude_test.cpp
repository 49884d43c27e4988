// docs/gx1.md section 13: the sensor's angles as the camera attitude.
#include "core/geometry/gx1_attitude.hpp"

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(Gx1Attitude, MapsRollPitchYawWithTheDocumentedSigns) {
  const Attitude a = camera_attitude_from_gx1({10.0, -5.0, 30.0});
  EXPECT_DOUBLE_EQ(a.phi, deg_to_rad(10.0));
  EXPECT_DOUBLE_EQ(a.theta, deg_to_rad(5.0));
  EXPECT_DOUBLE_EQ(a.psi, deg_to_rad(-30.0));
}

TEST(Gx1Attitude, NoseDownOnTheSensorTipsTheCameraTowardTheRoad) {
  // NED: positive pitch raises the nose. Nose down (negative) must be positive camera
  // pitch, which docs/geometry.md defines as tipping the view down.
  const Mat3 t = attitude_matrix(camera_attitude_from_gx1({0.0, -10.0, 0.0}));
  EXPECT_LT(t.col(2).z(), 0.0);
}

TEST(Gx1Attitude, ClockwiseHeadingTurnsTheViewRight) {
  // NED: positive yaw turns clockwise seen from above (north -> east), i.e. to the right;
  // docs/geometry.md's positive yaw turns the view left (+y).
  const Mat3 t = attitude_matrix(camera_attitude_from_gx1({0.0, 0.0, 20.0}));
  EXPECT_LT(t.col(2).y(), 0.0);
}

}  // namespace
}  // namespace ccdlane
