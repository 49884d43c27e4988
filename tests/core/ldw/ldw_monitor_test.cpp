// The per-frame LDW chain on noise-free solves of a known drift: DLC and TLC as the
// geometry says, the speed and time step taken from the inputs (or the [vehicle]
// default), availability after confirmation, one warning, and no allocation per frame.
#include "core/ldw/ldw_monitor.hpp"

#include <cmath>

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.hpp"

namespace ccdlane::ldw {
namespace {

constexpr double kWidth = 3.75;

LaneMeasurement solve_of(double offset, double heading) {
  LaneMeasurement m;
  m.value << kWidth / 2 - offset, -kWidth / 2 - offset, heading, 0.0, 0.05, 0.0;
  m.covariance = MeasurementMatrix::Identity() * 1e-6;
  m.covariance(kMeasuredHeading, kMeasuredHeading) = 1e-8;
  m.covariance(kMeasuredCurvature, kMeasuredCurvature) = 1e-10;
  m.present[kMeasuredRoll] = false;
  return m;
}

TEST(LdwMonitor, FollowsADriftWithTheGeometrysDlcAndTlcAndWarnsOnce) {
  LdwMonitor monitor;
  const double v = 20.0, lateral = 0.5, psi = std::asin(lateral / v);
  const double room = 0.5 * (kWidth - 0.12 - 1.8);  // a centred wheel's DLC
  int warnings = 0;
  double warned_at_dlc = 0.0;
  for (int k = 0; k < 300; ++k) {
    const double t = k / 30.0;
    const double offset = t < 2.0 ? 0.0 : lateral * (t - 2.0);
    const LaneMeasurement m = solve_of(offset, t < 2.0 ? 0.0 : psi);
    LdwFrameInput in;
    in.t_s = t;
    in.speed_mps = v;
    in.measurement = &m;
    const LdwResult& r = monitor.step(in);
    if (k < 4) {
      EXPECT_FALSE(r.decision.available);  // not yet confirmed
    }
    if (k == 10) {
      EXPECT_TRUE(r.decision.available);
      EXPECT_NEAR(r.dlc.left_m, room, 1e-3);
      EXPECT_NEAR(r.dlc.right_m, room, 1e-3);
    }
    if (t > 3.0 && r.dlc.left_m > 0.0) {
      const double wheel_offset = offset + 1.0 * std::sin(r.lane.value(kHeading));  // the axle 1 m ahead
      EXPECT_NEAR(r.dlc.left_m, room - wheel_offset, 5e-3) << t;
      EXPECT_NEAR(r.lateral_velocity_mps, lateral, 0.02) << t;
      ASSERT_TRUE(r.tlc_left_s) << t;
      EXPECT_NEAR(*r.tlc_left_s, r.dlc.left_m / r.lateral_velocity_mps, 1e-9);
      EXPECT_FALSE(r.tlc_right_s);
    }
    if (r.decision.fired != Side::none) {
      EXPECT_EQ(r.decision.fired, Side::left);
      warned_at_dlc = r.dlc.left_m;
      ++warnings;
    }
  }
  EXPECT_EQ(warnings, 1);
  EXPECT_NEAR(warned_at_dlc, 0.25, 0.5 / 30 + 0.01);
}

TEST(LdwMonitor, UsesTheVehicleTablesSpeedWithoutASpeedInput) {
  LdwConfig c;
  c.vehicle.speed_kmh = 50.0;
  LdwMonitor monitor(c);
  const LaneMeasurement m = solve_of(0.0, 0.0);
  LdwFrameInput in;
  in.measurement = &m;
  for (int k = 0; k < 10; ++k) {
    in.t_s = k / 30.0;
    monitor.step(in);
  }
  EXPECT_NEAR(monitor.result().speed_mps, 50.0 / 3.6, 1e-12);
  EXPECT_EQ(monitor.result().decision.reason, Availability::too_slow);
  in.speed_mps = 25.0;
  in.t_s += 1.0 / 30;
  EXPECT_EQ(monitor.step(in).decision.reason, Availability::none);
}

TEST(LdwMonitor, PassesFaultsThroughAndLosesTheLaneAfterCoasting) {
  LdwMonitor monitor;
  const LaneMeasurement m = solve_of(0.0, 0.0);
  LdwFrameInput in;
  in.speed_mps = 25.0;
  in.yaw_rate_radps = 0.0;  // with the gyro's rate the heading coasts well
  in.measurement = &m;
  for (int k = 0; k < 10; ++k) in.t_s = k / 30.0, monitor.step(in);
  in.gyro_ok = false;
  in.t_s += 1.0 / 30;
  EXPECT_EQ(monitor.step(in).decision.reason, Availability::gyro_fault);
  in.gyro_ok = true;
  in.vehicle_ok = false;
  in.t_s += 1.0 / 30;
  EXPECT_EQ(monitor.step(in).decision.reason, Availability::vehicle_fault);
  in.vehicle_ok = true;
  in.measurement = nullptr;
  in.t_s += 0.5;
  EXPECT_EQ(monitor.step(in).decision.reason, Availability::none);  // coasting, still confident
  in.t_s += 1.0;
  EXPECT_EQ(monitor.step(in).decision.reason, Availability::no_lane);
  EXPECT_EQ(monitor.result().lane.status, TrackStatus::lost);
  EXPECT_FALSE(monitor.result().tlc_left_s);
}

TEST(LdwMonitor, StepsWithoutAllocating) {
  LdwMonitor monitor;
  const LaneMeasurement m = solve_of(0.3, 0.02);
  LdwFrameInput in;
  in.speed_mps = 25.0;
  in.yaw_rate_radps = 0.01;
  in.measurement = &m;
  monitor.step(in);
  test::AllocationScope scope;
  for (int k = 1; k < 200; ++k) {
    in.t_s = k / 30.0;
    in.measurement = k % 7 ? &m : nullptr;
    in.indicator = k % 50 < 10 ? TurnIndicator::left : TurnIndicator::none;
    monitor.step(in);
  }
  monitor.reset();
  monitor.step(in);
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace ccdlane::ldw
