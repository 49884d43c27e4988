// The daemon's refinement glue on estimates made up with a known mount, fed to the
// estimator's refinement stage as ccdlaned configures it: off unless asked, the state
// file found through $STATE_DIRECTORY, saved once calibrated and at stop, loaded
// calibrated at once, a bad file one log line and uncalibrated, "not calibrated" for LDW
// out of range, and frames and status seconds that allocate nothing.
#include "daemon/online_calibration.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "base/log.hpp"
#include "daemon/allocation_counter.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/support/log_capture.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using calibration::OnlineMountState;

constexpr std::int64_t kSecond = 1'000'000'000;

using test::count_of;
using test::LogCapture;

Config online_config(const std::string& state_file) {
  Config c = default_config();
  c.attitude.psi_deg = 0.0;
  c.attitude.theta_deg = 5.0;
  c.calibration.online = true;
  c.calibration.frames_needed = 100;
  c.calibration.max_change_deg_per_min = 60.0;
  c.calibration.max_correction_deg = 3.0;
  c.calibration.state_file = state_file;
  c.calibration.save_period_s = 1.0;
  return c;
}

// Frames of a camera mounted yaw +1.5, pitch -2 off the configuration, at 30 fps, 90 km/h.
struct Frames {
  double psi_deg = 1.5, theta_deg = 3.0;
  std::mt19937_64 rng{11};
  std::int64_t n = 0;

  LaneEstimate next() {
    std::normal_distribution<double> noise(0.0, 0.2);
    LaneEstimate e;
    e.t_ns = n++ * kSecond / 30;
    e.ok = true;
    e.num_lines = 2;
    e.psi_deg = psi_deg + noise(rng);
    e.theta_deg = theta_deg + noise(rng);
    e.ldw.speed_mps = 25.0;
    return e;
  }
};

// The estimator's refinement stage as ccdlaned builds it for k.
MountRefinement stage_of(const OnlineCalibration& k) {
  LaneEstimatorOptions options = default_config().estimator_options();
  k.configure(options);
  return MountRefinement(options);
}

void drive(OnlineCalibration& k, MountRefinement& stage, Frames& f, int frames) {
  for (int i = 0; i < frames; ++i) k.share(stage.refine(f.next(), VehicleInputs{}));
}

class OnlineCalibrationTest : public ::testing::Test {
 protected:
  test::TempDir dir_;
  std::string path_ = dir_.file("mount-refinement.toml");
};

TEST_F(OnlineCalibrationTest, OffUnlessAsked) {
  Config c = default_config();
  const OnlineCalibration k(c);
  EXPECT_FALSE(k.enabled());
  EXPECT_EQ(k.status().state, OnlineMountState::off);
}

TEST_F(OnlineCalibrationTest, TheStateFileIsFoundInTheStateDirectory) {
  setenv("STATE_DIRECTORY", (dir_.path() + ":/elsewhere").c_str(), 1);
  const OnlineCalibration k(online_config(""));
  unsetenv("STATE_DIRECTORY");
  EXPECT_EQ(k.state_file(), path_);
  const OnlineCalibration none(online_config(""));
  EXPECT_EQ(none.state_file(), "") << "neither configured nor given by systemd: not kept";
}

TEST_F(OnlineCalibrationTest, LearnsSavesAndStartsCalibratedNextTime) {
  LogCapture log;
  {
    OnlineCalibration k(online_config(path_));
    MountRefinement stage = stage_of(k);
    EXPECT_EQ(count_of(log.text(), "no mount learned yet"), 1);
    EXPECT_EQ(k.status().state, OnlineMountState::uncalibrated);
    Frames f;
    drive(k, stage, f, 50);
    k.tick(1 * kSecond);
    EXPECT_EQ(k.status().state, OnlineMountState::calibrating);
    EXPECT_DOUBLE_EQ(k.status().progress, 0.5);
    drive(k, stage, f, 250);
    k.tick(3 * kSecond);  // calibrated, a save period after the first tick: saved
    EXPECT_EQ(k.status().state, OnlineMountState::calibrated);
    EXPECT_TRUE(std::filesystem::exists(path_));
    EXPECT_NEAR(k.status().applied.psi_deg, 1.5, 4 * 0.2 / std::sqrt(300.0));
    EXPECT_NEAR(k.status().applied.theta_deg, -2.0, 4 * 0.2 / std::sqrt(300.0));
    drive(k, stage, f, 30);
    k.stop();  // the last frames are saved too
  }
  const std::string text = log.text();
  EXPECT_EQ(count_of(text, "calibrating -> calibrated"), 1) << text;
  EXPECT_GE(count_of(text, "mount correction now"), 1) << text;
  EXPECT_NE(test::read_file(path_).find("frames = 330\n"), std::string::npos) << test::read_file(path_);

  const OnlineCalibration again(online_config(path_));
  EXPECT_EQ(again.status().state, OnlineMountState::calibrated);
  EXPECT_EQ(again.status().frames, 330);
  EXPECT_EQ(count_of(log.text(), "learned mount loaded"), 1);
}

TEST_F(OnlineCalibrationTest, ABadStateFileIsOneLineAndUncalibrated) {
  dir_.write("mount-refinement.toml", "format = 1\nconfigured_psi_deg = zero\n");
  LogCapture log;
  const OnlineCalibration k(online_config(path_));
  const std::string text = log.text();
  EXPECT_EQ(count_of(text, "\n"), 1) << text;
  EXPECT_EQ(count_of(text, path_ + ": not used: configured_psi_deg is not a number (line 2); starting uncalibrated"), 1)
      << text;
  EXPECT_EQ(k.status().state, OnlineMountState::uncalibrated);
  EXPECT_EQ(k.status().applied, calibration::MountAngles{});
}

// A FIFO as the state file once blocked start-up for ever; "/" said "no format version".
TEST_F(OnlineCalibrationTest, AStateFileThatIsNoRegularFileIsOneLineAndUncalibrated) {
  ASSERT_EQ(::mkfifo(path_.c_str(), 0600), 0);
  for (const std::string& path : {path_, std::string("/")}) {
    LogCapture log;
    const OnlineCalibration k(online_config(path));
    const std::string text = log.text();
    EXPECT_EQ(count_of(text, path + ": not used: not a regular file: not a state file; starting uncalibrated"), 1)
        << text;
    EXPECT_EQ(k.status().state, OnlineMountState::uncalibrated);
  }
}

TEST_F(OnlineCalibrationTest, OutOfRangeMakesLdwNotCalibratedAndIsNotSaved) {
  Config c = online_config(path_);
  c.calibration.max_correction_deg = 1.0;  // the frames say 1.5 and 2 degrees
  OnlineCalibration k(c);
  MountRefinement stage = stage_of(k);
  Frames f;
  drive(k, stage, f, 200);
  EXPECT_FALSE(stage.calibrated());
  k.tick(5 * kSecond);
  k.stop();
  EXPECT_EQ(k.status().state, OnlineMountState::out_of_range);
  EXPECT_FALSE(std::filesystem::exists(path_));
}

TEST_F(OnlineCalibrationTest, SlowFramesAreNotUsed) {
  OnlineCalibration k(online_config(path_));
  MountRefinement stage = stage_of(k);
  Frames f;
  for (int i = 0; i < 200; ++i) {
    LaneEstimate e = f.next();
    e.ldw.speed_mps = 10.0;  // 36 km/h
    VehicleInputs vehicle;
    k.share(stage.refine(e, vehicle));
  }
  EXPECT_EQ(k.status().frames, 0);
}

TEST_F(OnlineCalibrationTest, FramesAndStatusSecondsAllocateNothing) {
  OnlineCalibration k(online_config(path_));
  MountRefinement stage = stage_of(k);
  Frames f;
  drive(k, stage, f, 10);
  const std::uint64_t before = allocation_counter::in_this_thread();
  drive(k, stage, f, 300);
  k.tick(1 * kSecond);
  k.tick(3 * kSecond);  // with a save
  k.stop();
  EXPECT_EQ(allocation_counter::in_this_thread() - before, 0u);
  EXPECT_TRUE(std::filesystem::exists(path_));
}

}  // namespace
}  // namespace ccdlane
