// The synthetic drive's truth: consistent lane quantities, a lane change that moves the
// vehicle one lane right, gyro columns that map back to the camera attitude with the
// configured noise, determinism, and a drive that loops without a seam.
#include "core/synth/synth_drive.hpp"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"

namespace ccdlane {
namespace {

TEST(SynthDrive, LaneQuantitiesAgreeWithTheLines) {
  Config c = default_config();
  c.attitude = {0.5, 3.0, -0.2};
  const SynthDrive drive(c.synth, c.nominal_pose());
  ASSERT_EQ(drive.num_lines(), 4);
  for (std::uint64_t k = 0; k < 300; k += 7) {
    const SynthFrame f = drive.frame(k);
    ASSERT_EQ(f.num_lines, 4);
    EXPECT_EQ(f.ego_lane, 1);
    const double left = f.y0_mm[1], right = f.y0_mm[2];
    EXPECT_GT(left, 0.0);
    EXPECT_LT(right, 0.0);
    EXPECT_NEAR(left - right, f.lane_width_mm, 1e-9);
    EXPECT_NEAR(f.lateral_offset_mm, -(left + right) / 2, 1e-9);  // docs/interfaces.md's definition
    EXPECT_LE(std::abs(f.lateral_offset_mm), c.synth.weave_mm + 1e-9);
    for (int j = 1; j < 4; ++j) EXPECT_NEAR(f.y0_mm[j - 1] - f.y0_mm[j], 3600.0, 1e-9);
    // The vehicle's heading is in the camera yaw on top of the mount.
    EXPECT_NEAR(rad_to_deg(f.pose.attitude.psi), 0.5 + f.heading_deg, 1e-12);
    EXPECT_LE(std::abs(rad_to_deg(f.pose.attitude.theta) - 3.0), c.synth.pitch_bump_deg + 1e-9);
    EXPECT_LE(std::abs(rad_to_deg(f.pose.attitude.phi) + 0.2), c.synth.roll_sway_deg + 1e-9);
    EXPECT_EQ(f.pose.H_mm, 1400.0);
    EXPECT_EQ(f.t_ns, static_cast<std::int64_t>(std::llround(static_cast<double>(k) * 1e9 / 30.0)));
  }
}

TEST(SynthDrive, HeadingIsTheDirectionOfTheLateralMotion) {
  Config c = default_config();
  c.synth.rate_hz = 100;
  const SynthDrive drive(c.synth, c.nominal_pose());
  for (std::uint64_t k = 1; k < 600; k += 13) {
    const SynthFrame a = drive.frame(k - 1), b = drive.frame(k + 1);
    const double lateral_speed = (b.lateral_offset_mm - a.lateral_offset_mm) / 0.02;  // mm/s
    const double want = rad_to_deg(std::atan(lateral_speed / 25000.0));
    EXPECT_NEAR(drive.frame(k).heading_deg, want, 0.01);
  }
}

TEST(SynthDrive, LaneChangeMovesTheVehicleOneLaneRight) {
  Config c = default_config();
  c.synth.lane_change_at_s = 2.0;
  c.synth.lane_change_s = 3.0;
  c.synth.weave_mm = 0.0;
  const SynthDrive drive(c.synth, c.nominal_pose());
  const SynthFrame before = drive.frame(30), after = drive.frame(30 * 6);
  EXPECT_EQ(before.ego_lane, 1);
  EXPECT_EQ(after.ego_lane, 2);
  EXPECT_NEAR(after.y0_mm[0] - before.y0_mm[0], 3600.0, 1e-6);  // the road moved left
  EXPECT_NEAR(after.lateral_offset_mm, 0.0, 1e-6);
  // Mid-change the heading points right (negative) and the vehicle crosses line 2.
  const SynthFrame mid = drive.frame(105);
  EXPECT_LT(mid.heading_deg, -1.0);
  EXPECT_NEAR(mid.y0_mm[2], 0.0, 100.0);
}

TEST(SynthDrive, GyroColumnsAreTheTrueRollAndPitchPlusNoise) {
  Config c = default_config();
  c.attitude = {0.0, 2.0, 1.0};
  c.synth.gyro_noise_deg = 0.2;
  const SynthDrive drive(c.synth, c.nominal_pose());
  double sum_r = 0, sum_p = 0, sum_r2 = 0, sum_p2 = 0;
  const int n = 4000;
  for (int k = 0; k < n; ++k) {
    const SynthFrame f = drive.frame(static_cast<std::uint64_t>(k));
    const Attitude cam = camera_attitude_from_gx1(f.gyro);
    const double er = rad_to_deg(cam.phi - f.pose.attitude.phi), ep = rad_to_deg(cam.theta - f.pose.attitude.theta);
    EXPECT_NEAR(rad_to_deg(cam.psi), rad_to_deg(f.pose.attitude.psi), 1e-9);  // yaw carries no noise
    sum_r += er, sum_p += ep, sum_r2 += er * er, sum_p2 += ep * ep;
  }
  // Mean 0 +- 4 standard errors, sigma within 5%.
  EXPECT_NEAR(sum_r / n, 0.0, 4 * 0.2 / std::sqrt(n));
  EXPECT_NEAR(sum_p / n, 0.0, 4 * 0.2 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sum_r2 / n), 0.2, 0.01);
  EXPECT_NEAR(std::sqrt(sum_p2 / n), 0.2, 0.01);
}

TEST(SynthDrive, SameSeedSameDriveOtherSeedOtherDrive) {
  Config c = default_config();
  const SynthDrive a(c.synth, c.nominal_pose()), b(c.synth, c.nominal_pose());
  c.synth.seed = 2;
  const SynthDrive other(c.synth, c.nominal_pose());
  EXPECT_EQ(a.frame(17).gyro.roll_deg, b.frame(17).gyro.roll_deg);
  EXPECT_EQ(a.frame(17).pose.attitude.theta, b.frame(17).pose.attitude.theta);
  EXPECT_NE(a.frame(17).gyro.roll_deg, other.frame(17).gyro.roll_deg);
  EXPECT_NE(a.frame(17).pose.attitude.theta, other.frame(17).pose.attitude.theta);
}

// The largest change from one frame to the next of what the lane filter and the gyro
// see: offset (mm), heading, pitch and roll (deg).
struct Step {
  double offset_mm = 0, heading_deg = 0, theta_deg = 0, phi_deg = 0;
  void widen(const SynthFrame& a, const SynthFrame& b) {
    offset_mm = std::max(offset_mm, std::abs(b.lateral_offset_mm - a.lateral_offset_mm));
    heading_deg = std::max(heading_deg, std::abs(b.heading_deg - a.heading_deg));
    theta_deg = std::max(theta_deg, rad_to_deg(std::abs(b.pose.attitude.theta - a.pose.attitude.theta)));
    phi_deg = std::max(phi_deg, rad_to_deg(std::abs(b.pose.attitude.phi - a.pose.attitude.phi)));
  }
  // Each of this step's no larger than `other`'s, up to rounding.
  bool within(const Step& other) const {
    return offset_mm <= other.offset_mm + 1e-6 && heading_deg <= other.heading_deg + 1e-9 &&
           theta_deg <= other.theta_deg + 1e-9 && phi_deg <= other.phi_deg + 1e-9;
  }
};

// A looping source plays frames 0..n-1 and then frame 0 again: the step from frame n-1 to
// frame 0 must be an ordinary step of the drive. Without the loop it was a jump of up to
// 400 mm in the offset, and of the yaw, which the emulated gyro's rate made a spike.
TEST(SynthDrive, ALoopingDriveRepeatsWithoutASeam) {
  const Config c = default_config();
  const double dash_cycle_mm = c.synth.dash_length_mm + c.synth.dash_gap_mm;
  for (const int n : {10, 100, 180, 240}) {
    SCOPED_TRACE("a loop of " + std::to_string(n) + " frames");
    const auto last = static_cast<std::uint64_t>(n - 1);
    const SynthDrive looping(c.synth, c.nominal_pose(), n / c.synth.rate_hz), plain(c.synth, c.nominal_pose());
    Step inside, seam, plain_inside, plain_seam;
    for (std::uint64_t k = 1; k <= last; ++k) {
      inside.widen(looping.frame(k - 1), looping.frame(k));
      plain_inside.widen(plain.frame(k - 1), plain.frame(k));
    }
    seam.widen(looping.frame(last), looping.frame(0));
    plain_seam.widen(plain.frame(last), plain.frame(0));
    EXPECT_TRUE(seam.within(inside)) << "offset " << seam.offset_mm << " mm against " << inside.offset_mm;
    EXPECT_FALSE(plain_seam.within(plain_inside)) << "the drive as configured jumps there";
    // The dashes are where they were: the loop is a whole number of dash cycles.
    const double along = std::fmod(looping.frame(static_cast<std::uint64_t>(n)).odometer_mm, dash_cycle_mm);
    EXPECT_NEAR(std::min(along, dash_cycle_mm - along), 0.0, 1e-6);
    // And the drive is the one asked for, its periods rounded to whole cycles of the loop:
    // the speed within half a dash cycle a loop; the weave as wide where its period is
    // not shortened (6 s in 6 or 8 s), narrower by the square of the shortening where it
    // is (3.3 s for 6: 0.31 of its width), never turning the car harder than configured.
    const double loop_s = n / c.synth.rate_hz;
    const double speed_mps = looping.frame(1).odometer_mm / 1000.0 * c.synth.rate_hz;
    EXPECT_LE(std::abs(speed_mps - c.synth.speed_mps), 0.5 * dash_cycle_mm / 1000.0 / loop_s + 1e-9);
    double widest = 0.0;
    for (std::uint64_t k = 0; k <= last; ++k) widest = std::max(widest, std::abs(looping.frame(k).lateral_offset_mm));
    const double weave_period_s = loop_s / std::max(1.0, std::round(loop_s / c.synth.weave_period_s));
    const double shorter = std::min(1.0, weave_period_s / c.synth.weave_period_s);
    const double width = c.synth.weave_mm * shorter * shorter;
    EXPECT_NEAR(widest, width, 0.02 * width);
    EXPECT_LE(inside.heading_deg, plain_inside.heading_deg * 1.05) << "no faster than configured";
  }
}

}  // namespace
}  // namespace ccdlane
