// Mount calibration against the truth: drives rendered with a known mis-mount (yaw +1.5,
// pitch -2, roll +0.5 degrees, H 10 % high) solved with the nominal mount, recovered
// within 3 of the reported sigmas, sigmas shrinking with the drive's length; bends, turns
// and lane changes kept out; the refusals. Plus the bookkeeping on hand-made frames.
#include "core/calibration/mount_calibration.hpp"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "core/lane/lane_estimator.hpp"
#include "tests/core/synth/rendered_road.hpp"

namespace ccdlane::calibration {
namespace {

constexpr double kRateHz = 10.0;

// The configured (nominal) mount: what the user believes.
Config nominal_config() {
  Config c = test::small_reference_camera();
  c.detection.max_picks = 160;
  c.attitude = {0.0, 5.0, 0.0};
  c.H_mm = 1400.0;
  c.synth.rate_hz = kRateHz;
  return c;
}

// The camera as it really sits: yaw +1.5, pitch -2, roll +0.5 degrees, H 10 % higher.
Config true_config(const Config& nominal) {
  Config t = nominal;
  t.attitude = {nominal.attitude.psi_deg + 1.5, nominal.attitude.theta_deg - 2.0, nominal.attitude.phi_deg + 0.5};
  t.H_mm = nominal.H_mm * 1.1;
  return t;
}

// `seconds` of the true camera's drive, rendered once (the calibration passes over it twice).
struct Recording {
  std::vector<std::vector<std::uint8_t>> images;
  std::vector<SynthFrame> truth;
  int width = 0, height = 0;
};

Recording render(const Config& truth, double seconds) {
  test::RenderedRoad road(truth);
  Recording r;
  r.width = truth.camera.Nu, r.height = truth.camera.Nv;
  const auto count = static_cast<std::uint64_t>(std::llround(seconds * kRateHz));
  for (std::uint64_t k = 0; k < count; ++k) {
    r.truth.push_back(road.render(k));
    r.images.push_back(road.px);
  }
  return r;
}

MountOptions options_for(const Config& nominal) {
  MountOptions o;
  o.nominal_H_mm = nominal.H_mm;
  o.lane_width_mm = {3600.0, 200.0};
  return o;
}

// The first `count` frames solved with the nominal mount, as `ccdlane calibrate mount` does.
MountCalibration calibrate(const Config& nominal, const Recording& rec, std::size_t count, const MountOptions& o) {
  const auto pass = [&](double phi_deg) {
    LaneEstimator estimator(mount_estimator_options(nominal.estimator_options(), phi_deg));
    std::vector<MountFrame> frames;
    for (std::size_t k = 0; k < count; ++k) {
      const ImageView view{rec.images[k].data(), rec.width, rec.height, rec.width, PixelFormat::mono8, 8};
      const LaneEstimate& e = estimator.estimate(view, k, rec.truth[k].t_ns, std::nullopt);
      frames.push_back(mount_frame(e, estimator.solution(), rec.truth[k].gyro, phi_deg, nominal.H_mm));
    }
    return frames;
  };
  return run_mount_passes(pass, nominal.attitude.phi_deg, o);
}

MountCalibration calibrate(const Config& nominal, const Config& truth, double seconds) {
  const Recording rec = render(truth, seconds);
  return calibrate(nominal, rec, rec.images.size(), options_for(nominal));
}

void expect_within_3_sigma(const MountCalibration& m, const Config& truth, const char* what) {
  ASSERT_EQ(m.status, MountStatus::ok) << what << ": " << m.message;
  EXPECT_TRUE(m.phi_determined) << what;
  EXPECT_NEAR(m.psi_deg, truth.attitude.psi_deg, 3 * m.sigma_psi_deg) << what;
  EXPECT_NEAR(m.theta_deg, truth.attitude.theta_deg, 3 * m.sigma_theta_deg) << what;
  EXPECT_NEAR(m.phi_deg, truth.attitude.phi_deg, 3 * m.sigma_phi_deg) << what;
  EXPECT_NEAR(m.H_mm, truth.H_mm, 3 * m.sigma_H_mm) << what;
}

void print(const MountCalibration& m, const Config& truth, const char* what) {
  std::printf(
      "%s: %.1f s straight, %d blocks, %d/%d frames; psi %.3f +- %.3f (true %.3f), theta %.3f +- %.3f "
      "(true %.3f), phi %.3f +- %.3f (true %.3f), H %.0f +- %.0f (true %.0f), width at nominal H %.0f +- %.0f\n",
      what, m.straight_s, m.blocks, m.frames_kept, m.frames, m.psi_deg, m.sigma_psi_deg, truth.attitude.psi_deg,
      m.theta_deg, m.sigma_theta_deg, truth.attitude.theta_deg, m.phi_deg, m.sigma_phi_deg, truth.attitude.phi_deg,
      m.H_mm, m.sigma_H_mm, truth.H_mm, m.measured_width_mm, m.sigma_measured_width_mm);
}

TEST(MountCalibration, RecoversTheMisMountWithin3SigmaAndTheSigmasShrinkWithDriveLength) {
  const Config nominal = nominal_config();
  const Config truth = true_config(nominal);
  const Recording rec = render(truth, 40.0);
  const MountCalibration short_drive =
      calibrate(nominal, rec, static_cast<std::size_t>(10 * kRateHz), options_for(nominal));
  const MountCalibration long_drive = calibrate(nominal, rec, rec.images.size(), options_for(nominal));
  print(short_drive, truth, "10 s");
  print(long_drive, truth, "40 s");
  expect_within_3_sigma(short_drive, truth, "10 s");
  expect_within_3_sigma(long_drive, truth, "40 s");
  EXPECT_LT(long_drive.sigma_psi_deg, short_drive.sigma_psi_deg);
  EXPECT_LT(long_drive.sigma_theta_deg, short_drive.sigma_theta_deg);
  EXPECT_LT(long_drive.sigma_phi_deg, short_drive.sigma_phi_deg);
  EXPECT_LT(long_drive.sigma_measured_width_mm, short_drive.sigma_measured_width_mm);
  // H's sigma is mostly the lane-width prior's (0.2 / 3.6 = 5.6 %), which no drive shrinks.
  EXPECT_GT(long_drive.sigma_H_mm, 0.055 * long_drive.H_mm);

  // A known lane width leaves only the measurement's spread in H.
  MountOptions known = options_for(nominal);
  known.lane_width_mm = {3600.0, 0.0};
  const MountCalibration measured = calibrate(nominal, rec, rec.images.size(), known);
  print(measured, truth, "40 s, width known");
  expect_within_3_sigma(measured, truth, "40 s, width known");
  EXPECT_LT(measured.sigma_H_mm, 0.25 * long_drive.sigma_H_mm);
}

TEST(MountCalibration, ALaneChangeIsCutOutNotTakenForYaw) {
  const Config nominal = nominal_config();
  Config truth = true_config(nominal);
  truth.synth.lane_change_at_s = 6.0;  // 6..10 s: to the lane on the right
  const MountCalibration m = calibrate(nominal, truth, 18.0);
  print(m, truth, "18 s with a lane change");
  expect_within_3_sigma(m, truth, "lane change");
  EXPECT_GE(m.stretches, 2);
  EXPECT_GT(m.frames_lane_change, static_cast<int>(2 * kRateHz));
}

TEST(MountCalibration, RefusesADriveTooShort) {
  const Config nominal = nominal_config();
  const MountCalibration m = calibrate(nominal, true_config(nominal), 3.0);
  EXPECT_EQ(m.status, MountStatus::too_short) << m.message;
  EXPECT_NE(m.message.find("straight driving"), std::string::npos) << m.message;
}

TEST(MountCalibration, RefusesARoadWithoutLines) {
  const Config nominal = nominal_config();
  Config truth = true_config(nominal);
  truth.synth.paint_grey = truth.synth.asphalt_grey;  // the paint is worn off
  const MountCalibration m = calibrate(nominal, truth, 8.0);
  EXPECT_EQ(m.status, MountStatus::no_lines) << m.message;
}

TEST(MountCalibration, RefusesADriveOnlyOnABend) {
  const Config nominal = nominal_config();
  Config truth = true_config(nominal);
  truth.synth.curvature_per_mm = 1.0 / (2 * 400e3);  // radius 400 m, all the way
  const MountCalibration m = calibrate(nominal, truth, 10.0);
  EXPECT_EQ(m.status, MountStatus::only_curves) << m.message;
  EXPECT_GT(m.frames_curved, m.frames_with_lane / 2);
}

TEST(MountCalibration, ABendOf800MetresCounts) {
  // The frames are solved with the road's curvature: on a freeway bend the lane's
  // direction at the camera is still the vehicle's, and the mount comes out as on a
  // straight road.
  const Config nominal = nominal_config();
  Config truth = true_config(nominal);
  truth.synth.curvature_per_mm = 1.0 / (2 * 800e3);
  const MountCalibration m = calibrate(nominal, truth, 10.0);
  print(m, truth, "10 s on a bend of 800 m");
  expect_within_3_sigma(m, truth, "800 m bend");
  EXPECT_EQ(m.frames_curved, 0);
}

// Hand-made frames: straight road, the heading wandering by +-1 degree with a 6 s period.
std::vector<MountFrame> steady_frames(double seconds, double psi_deg) {
  std::vector<MountFrame> frames;
  for (int k = 0; k < static_cast<int>(seconds * kRateHz); ++k) {
    const double t = k / kRateHz;
    MountFrame f;
    f.t_ns = static_cast<std::int64_t>(std::llround(t * 1e9));
    f.lane = true;
    f.psi_deg = psi_deg + std::sin(2 * kPi * t / 6.0);
    f.theta_deg = 3.0;
    f.phi_deg = 0.0;
    f.sigma_psi_deg = f.sigma_theta_deg = 0.05;
    f.lane_width_mm = 3600.0;
    f.sigma_lane_width_mm = 10.0;
    f.gyro_yaw_deg = -f.psi_deg;
    frames.push_back(f);
  }
  return frames;
}

TEST(MountCalibration, SigmaIsTheBlockSpreadNotTheFramesOwn) {
  const MountCalibration m = calibrate_mount(steady_frames(24.0, 1.0));
  ASSERT_EQ(m.status, MountStatus::ok) << m.message;
  EXPECT_EQ(m.blocks, 24);
  EXPECT_NEAR(m.psi_deg, 1.0, 3 * m.sigma_psi_deg);
  // Blocks of 1 s through a 1-degree wave scatter by tenths of a degree: more than the
  // frames' own 0.05 over 24 blocks.
  EXPECT_GT(m.sigma_psi_deg, 0.05);
  // Theta never moves: its sigma is the frames' own, once per block.
  EXPECT_NEAR(m.sigma_theta_deg, 0.05 / std::sqrt(24.0), 1e-9);
  EXPECT_NEAR(m.H_mm, 1400.0, 1e-9);
  EXPECT_NEAR(m.sigma_H_mm, 1400.0 * std::hypot(200.0, 10.0 / std::sqrt(24.0)) / 3600.0, 1e-6);
}

TEST(MountCalibration, OffsetNoiseAt25FramesASecondIsNoLaneChange) {
  // A lateral offset measured to +-3 cm each frame changes by up to 6 cm in 40 ms, 1.5 m/s
  // taken frame to frame; over the 1 s window it is no speed at all. A real lane change
  // (3.6 m in 4 s) is still caught.
  std::vector<MountFrame> frames;
  for (int k = 0; k < 250; ++k) {
    MountFrame f;
    f.t_ns = 40'000'000LL * k;
    f.lane = true;
    f.theta_deg = 3.0;
    f.sigma_psi_deg = f.sigma_theta_deg = 0.05;
    f.lane_width_mm = 3600.0;
    f.sigma_lane_width_mm = 10.0;
    f.lateral_offset_mm = (k % 2 == 0 ? 30.0 : -30.0);
    frames.push_back(f);
  }
  MountCalibration m = calibrate_mount(frames);
  ASSERT_EQ(m.status, MountStatus::ok) << m.message;
  EXPECT_EQ(m.frames_lane_change, 0);
  EXPECT_EQ(m.frames_kept, 250);
  for (int k = 100; k < 150; ++k) frames[static_cast<std::size_t>(k)].lateral_offset_mm += 900.0 * (k - 100) * 0.04;
  for (int k = 150; k < 250; ++k) frames[static_cast<std::size_t>(k)].lateral_offset_mm += 1800.0;
  m = calibrate_mount(frames);
  EXPECT_GT(m.frames_lane_change, 20);
}

TEST(MountCalibration, AFrameWithoutLinesNowAndThenDoesNotEndAStretch) {
  std::vector<MountFrame> frames = steady_frames(10.0, 0.0);
  for (std::size_t k = 3; k < frames.size(); k += 7) frames[k].lane = false;
  const MountCalibration m = calibrate_mount(frames);
  ASSERT_EQ(m.status, MountStatus::ok) << m.message;
  EXPECT_EQ(m.stretches, 1);
  EXPECT_NEAR(m.straight_s, 10.0, 0.2);
}

TEST(MountCalibration, StillsAreEachOneSample) {
  // Stills of unrelated clips: no times, each its own heading. The mean of the stills and
  // its standard error; fewer than min_stills are refused.
  std::vector<MountFrame> frames = steady_frames(2.0, 0.5);  // 20 stills, headings 0.5 +- 1 degree
  for (MountFrame& f : frames) f.t_ns = 0;
  MountOptions o;
  o.stills = true;
  MountCalibration m = calibrate_mount(frames, o);
  ASSERT_EQ(m.status, MountStatus::ok) << m.message;
  EXPECT_EQ(m.frames_kept, 20);
  EXPECT_EQ(m.blocks, 20);
  double mean = 0.0, sum2 = 0.0;
  for (const MountFrame& f : frames) mean += f.psi_deg / 20.0;
  for (const MountFrame& f : frames) sum2 += (f.psi_deg - mean) * (f.psi_deg - mean);
  EXPECT_NEAR(m.psi_deg, mean, 1e-9);
  EXPECT_NEAR(m.sigma_psi_deg, std::sqrt(sum2 / 19.0 / 20.0), 1e-9);
  frames.resize(9);
  m = calibrate_mount(frames, o);
  EXPECT_EQ(m.status, MountStatus::too_short);
  EXPECT_NE(m.message.find("only 9 of the 9 stills"), std::string::npos) << m.message;
}

TEST(MountCalibration, TurnsSeenByTheGyroAreDropped) {
  std::vector<MountFrame> frames = steady_frames(20.0, 0.0);
  for (std::size_t k = 50; k < 100; ++k) *frames[k].gyro_yaw_deg += 0.5 * static_cast<double>(k - 50);  // 5 deg/s
  const MountCalibration m = calibrate_mount(frames);
  ASSERT_EQ(m.status, MountStatus::ok) << m.message;
  EXPECT_EQ(m.frames_turning, 50);
  EXPECT_EQ(m.stretches, 2);
}

TEST(MountCalibration, EqualLanesGiveTheRoll) {
  // Four lines 3.6 m apart seen from 1.4 m, solved with a roll 0.7 degrees off: their
  // angles from the vertical are all turned by 0.7 degrees.
  const double H = 1400.0, d = deg_to_rad(0.7);
  double y0[4];
  for (int j = 0; j < 4; ++j) y0[j] = H * std::tan(std::atan((5400.0 - 3600.0 * j) / H) + d);
  const auto roll = equal_lanes_roll_deg(y0, H);
  ASSERT_TRUE(roll);
  EXPECT_NEAR(*roll, 0.7, 1e-6);
  EXPECT_FALSE(equal_lanes_roll_deg(std::span<const double>(y0, 2), H));
}

TEST(MountCalibration, RefusalsSayWhy) {
  std::vector<MountFrame> frames = steady_frames(20.0, 0.0);
  for (MountFrame& f : frames) f.lane = false;
  EXPECT_EQ(calibrate_mount(frames).status, MountStatus::no_lines);
  frames = steady_frames(20.0, 0.0);
  for (MountFrame& f : frames) f.c_per_mm = 2e-6;  // radius 250 m
  EXPECT_EQ(calibrate_mount(frames).status, MountStatus::only_curves);
  frames = steady_frames(3.5, 0.0);
  const MountCalibration m = calibrate_mount(frames);
  EXPECT_EQ(m.status, MountStatus::too_short);
  EXPECT_NE(m.message.find("only 3.5 s"), std::string::npos) << m.message;
}

}  // namespace
}  // namespace ccdlane::calibration
