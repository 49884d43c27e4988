// The front wheels' DLC: the centred vehicle's margins, the sign of every input, and
// agreement with exact rigid-body geometry on a circular lane.
#include "core/ldw/vehicle.hpp"

#include <cmath>

#include <gtest/gtest.h>

namespace ccdlane::ldw {
namespace {

constexpr double kLine = 0.12;

VehicleConfig car() {
  VehicleConfig v;
  v.width_mm = 1800.0;
  v.front_axle_behind_camera_mm = -1000.0;
  v.camera_left_of_centre_mm = 0.0;
  return v;
}

TEST(VehicleConfig, DefaultsAreTheIssuesReferenceVehicle) {
  const VehicleConfig v;
  EXPECT_EQ(v.speed_kmh, 72.0);
  EXPECT_EQ(v.width_mm, 1800.0);
}

TEST(DistanceToLineCrossing, CentredVehicleHasTheLanesMarginOnBothSides) {
  const SideDistances d = distance_to_line_crossing({0.0, 0.0, 0.0, 3.75}, car(), kLine);
  EXPECT_NEAR(d.left_m, (3.75 - kLine - 1.8) / 2, 1e-12);
  EXPECT_NEAR(d.right_m, (3.75 - kLine - 1.8) / 2, 1e-12);
}

TEST(DistanceToLineCrossing, OffsetAndCameraPlacementMoveTheWheelsTheDocumentedWay) {
  const double centred = (3.75 - kLine - 1.8) / 2;
  const SideDistances left_of_centre = distance_to_line_crossing({0.3, 0.0, 0.0, 3.75}, car(), kLine);
  EXPECT_NEAR(left_of_centre.left_m, centred - 0.3, 1e-12);
  EXPECT_NEAR(left_of_centre.right_m, centred + 0.3, 1e-12);
  // A camera 0.2 m left of the vehicle's centre, centred in the lane: the vehicle is
  // 0.2 m right of it.
  VehicleConfig v = car();
  v.camera_left_of_centre_mm = 200.0;
  const SideDistances cam_left = distance_to_line_crossing({0.0, 0.0, 0.0, 3.75}, v, kLine);
  EXPECT_NEAR(cam_left.left_m, centred + 0.2, 1e-12);
  EXPECT_NEAR(cam_left.right_m, centred - 0.2, 1e-12);
}

TEST(DistanceToLineCrossing, HeadingSwingsTheAxleAheadOfTheCameraTowardThatSide) {
  const double psi = 0.03;  // pointing left
  const double centred = (3.75 - kLine - 1.8) / 2;
  const SideDistances ahead = distance_to_line_crossing({0.0, psi, 0.0, 3.75}, car(), kLine);
  EXPECT_LT(ahead.left_m, centred);  // the axle 1 m ahead has moved left
  EXPECT_NEAR(ahead.left_m, centred - (1.0 * std::sin(psi) + 0.9 * (std::cos(psi) - 1.0)), 1e-12);
  VehicleConfig behind = car();
  behind.front_axle_behind_camera_mm = 1000.0;
  EXPECT_GT(distance_to_line_crossing({0.0, psi, 0.0, 3.75}, behind, kLine).left_m, centred);
}

// The lane as a circle of radius R about (0, R) (bending left), the camera at lateral
// offset d with heading psi: the wheel's distance from the centre gives its exact
// position in the lane.
TEST(DistanceToLineCrossing, AgreesWithExactGeometryOnACircularLaneToAMillimetre) {
  for (const double R : {500.0, -500.0, 800.0}) {
    for (const double psi : {-0.04, 0.0, 0.05}) {
      const double d = 0.25, w = 3.6;
      const LanePose pose{d, psi, 1.0 / R, w};
      const VehicleConfig v = car();
      // Camera at (0, d), the circle's centre at (0, R), lane centre at radius |R|.
      const double ahead = 1.0;
      for (const double left : {0.9, -0.9}) {
        const double x = ahead * std::cos(psi) - left * std::sin(psi);
        const double y = d + ahead * std::sin(psi) + left * std::cos(psi);
        const double exact = R > 0 ? R - std::hypot(x, y - R) : R + std::hypot(x, y - R);
        EXPECT_NEAR(lateral_position_in_lane_m(pose, ahead, left), exact, 1e-3) << "R " << R << " psi " << psi;
      }
      const SideDistances dlc = distance_to_line_crossing(pose, v, kLine);
      EXPECT_NEAR(dlc.left_m + dlc.right_m, w - kLine - 1.8 * std::cos(psi), 1e-3);
    }
  }
}

}  // namespace
}  // namespace ccdlane::ldw
