// The vehicle drive's truth against independent geometry: a centred vehicle's wheel
// margins on a straight road and on a circle (wheels placed by hand on the circle), the
// drift's lateral velocity and heading, clothoid curvature, lane changes with their
// indicator, and the frame handed to the renderer.
#include "core/synth/vehicle_drive.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "app/config.hpp"

namespace ccdlane {
namespace {

constexpr double kRoom = 0.5 * (3.75 - 0.12 - 1.8);  // a centred wheel's margin

ldw::VehicleConfig car() { return {}; }  // 1.8 m wide, axle 1 m ahead of the camera, centred

TEST(VehicleDrive, CentredOnAStraightRoadTheWheelsHaveTheLanesMargin) {
  VehicleScenario s;
  const VehicleDrive d(s, car());
  const VehicleFrame f = d.frame(90);
  EXPECT_NEAR(f.t_s, 3.0, 1e-12);
  EXPECT_NEAR(f.speed_mps, 20.0, 1e-6);
  EXPECT_NEAR(f.yaw_rate_radps, 0.0, 1e-6);
  EXPECT_NEAR(f.heading_rad, 0.0, 1e-9);
  EXPECT_EQ(f.ego_lane, 1);
  EXPECT_NEAR(f.left_line_m, 1.875, 1e-12);
  EXPECT_NEAR(f.right_line_m, -1.875, 1e-12);
  EXPECT_NEAR(f.wheel_dlc.left_m, kRoom, 1e-9);
  EXPECT_NEAR(f.wheel_dlc.right_m, kRoom, 1e-9);
  EXPECT_EQ(f.indicator, ldw::TurnIndicator::none);
  EXPECT_EQ(d.num_frames(), 601u);  // 20 s at 30 Hz, both ends
}

TEST(VehicleDrive, OnACircleTheWheelsAreWhereTheCircleSaysAndTheYawRateIsSpeedOverRadius) {
  for (const double R : {500.0, -500.0}) {
    VehicleScenario s;
    s.road = {{1e9, 1.0 / R}};
    const VehicleDrive d(s, car());
    const VehicleFrame f = d.frame(300);
    EXPECT_NEAR(f.yaw_rate_radps, 20.0 / R, 1e-6);
    EXPECT_NEAR(f.heading_rad, 0.0, 1e-6);
    EXPECT_NEAR(f.curvature_per_m, 1.0 / R, 1e-15);
    // The camera on the circle of radius |R| (the centre lane's centre), facing along
    // it; a wheel 1 m ahead and 0.9 m to the side is sqrt(1 + (|R| -+ 0.9)^2) from the
    // circle's centre.
    const double r = std::abs(R), toward_centre = R > 0 ? 1.0 : -1.0;
    const double left_wheel_n = toward_centre * (r - std::hypot(1.0, r - toward_centre * 0.9));
    const double right_wheel_n = toward_centre * (r - std::hypot(1.0, r + toward_centre * 0.9));
    EXPECT_NEAR(f.wheel_dlc.left_m, (1.875 - 0.06) - left_wheel_n, 1e-6) << R;
    EXPECT_NEAR(f.wheel_dlc.right_m, right_wheel_n + (1.875 - 0.06), 1e-6) << R;
  }
}

TEST(VehicleDrive, DriftReachesItsLateralVelocityAfterTheRamp) {
  VehicleScenario s;
  s.drift_at_s = 2.0;
  s.drift_mps = -0.8;
  s.drift_ramp_s = 1.0;
  const VehicleDrive d(s, car());
  const VehicleFrame a = d.frame(105), b = d.frame(120);  // 3.5 s and 4 s, still in the lane
  EXPECT_NEAR(a.lateral_velocity_mps, -0.8, 1e-6);
  EXPECT_NEAR(a.heading_rad, std::atan2(-0.8, 20.0), 1e-6);
  EXPECT_NEAR(a.speed_mps, std::hypot(20.0, 0.8), 1e-6);
  ASSERT_EQ(b.ego_lane, a.ego_lane);
  EXPECT_NEAR(b.wheel_dlc.right_m - a.wheel_dlc.right_m, -0.4, 1e-6);
  EXPECT_NEAR(b.wheel_dlc.left_m - a.wheel_dlc.left_m, 0.4, 1e-6);
  // Half way through the ramp, half the velocity.
  EXPECT_NEAR(d.frame(75).lateral_velocity_mps, -0.4, 1e-6);
}

TEST(VehicleDrive, ClothoidsRampTheCurvatureAndACentredCameraFollowsTheRoad) {
  VehicleScenario s;
  s.road = {{100.0, 0.0}, {1e9, 1.0 / 500, 100.0}};
  const VehicleDrive d(s, car());
  const VehicleFrame mid = d.frame(225);  // s = 150 m: half way into the curve
  EXPECT_NEAR(mid.curvature_per_m, 0.5 / 500, 1e-12);
  EXPECT_NEAR(mid.yaw_rate_radps, 20.0 * 0.5 / 500, 1e-5);
  EXPECT_NEAR(mid.heading_rad, 0.0, 1e-6);
  EXPECT_NEAR(mid.wheel_dlc.left_m + mid.wheel_dlc.right_m, 2 * kRoom, 1e-3);
}

TEST(VehicleDrive, LaneChangeMovesTheEgoLaneAndSignalsWhenAsked) {
  VehicleScenario s;
  s.lane_changes.push_back({5.0, 4.0, 1, true, 1.5});
  const VehicleDrive d(s, car());
  EXPECT_EQ(d.frame(100).indicator, ldw::TurnIndicator::none);  // 3.3 s
  EXPECT_EQ(d.frame(110).indicator, ldw::TurnIndicator::left);  // 3.7 s
  EXPECT_EQ(d.frame(240).indicator, ldw::TurnIndicator::left);  // 8.0 s
  EXPECT_EQ(d.frame(250).indicator, ldw::TurnIndicator::none);  // 8.3 s
  EXPECT_EQ(d.frame(200).ego_lane, 1);                          // 6.7 s: not yet across
  const VehicleFrame end = d.frame(400);
  EXPECT_EQ(end.ego_lane, 0);
  EXPECT_NEAR(end.offset_m, 0.0, 1e-9);
  EXPECT_NEAR(end.wheel_dlc.left_m, kRoom, 1e-9);
  // At the middle (7 s) the camera is on the line: the offset jumps by a lane width.
  const VehicleFrame before = d.frame(209), after = d.frame(211);
  EXPECT_EQ(before.ego_lane, 1);
  EXPECT_EQ(after.ego_lane, 0);
  EXPECT_NEAR(before.offset_m - after.offset_m, 3.75, 0.1);
  VehicleScenario quiet = s;
  quiet.lane_changes[0].signalled = false;
  EXPECT_EQ(VehicleDrive(quiet, car()).frame(150).indicator, ldw::TurnIndicator::none);
}

TEST(VehicleDrive, IsPureAndSeeded) {
  VehicleScenario s;
  s.weave_m = {0.1, 0.04};
  const VehicleDrive a(s, car()), b(s, car());
  EXPECT_EQ(a.frame(77).offset_m, b.frame(77).offset_m);
  EXPECT_EQ(a.frame(77).wheel_dlc.left_m, a.frame(77).wheel_dlc.left_m);
  s.seed = 2;
  EXPECT_NE(VehicleDrive(s, car()).frame(77).offset_m, a.frame(77).offset_m);
}

TEST(VehicleDrive, SynthFrameShowsTheSameRoadToTheRenderer) {
  Config c = default_config();
  VehicleScenario s;
  s.road = {{1e9, 1.0 / 600}};
  s.drift_at_s = 1.0;
  s.drift_mps = 0.3;
  const VehicleDrive d(s, car());
  const VehicleFrame v = d.frame(100);
  const SynthFrame f = d.synth_frame(100, c.nominal_pose(), c.synth.gyro_noise_deg);
  ASSERT_EQ(f.num_lines, 4);
  EXPECT_NEAR(f.y0_mm[1], v.left_line_m * 1000.0, 1e-9);
  EXPECT_NEAR(f.y0_mm[2], v.right_line_m * 1000.0, 1e-9);
  EXPECT_NEAR(f.c_per_mm, 0.5 / 600 * 1e-3, 1e-15);
  EXPECT_NEAR(f.pose.attitude.psi, deg_to_rad(c.attitude.psi_deg) + v.heading_rad, 1e-12);
  EXPECT_NEAR(f.pose.attitude.theta, v.pitch_rad, 1e-12);
  EXPECT_EQ(f.pose.H_mm, c.H_mm);
  EXPECT_EQ(f.ego_lane, v.ego_lane);
  EXPECT_EQ(f.t_ns, std::llround(100.0 / 30 * 1e9));
}

}  // namespace
}  // namespace ccdlane
