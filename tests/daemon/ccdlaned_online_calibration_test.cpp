// ccdlaned's online mount refinement as a process: a drive rendered by `ccdlane synth`
// with the camera mounted yaw +1.5 and pitch -2 degrees off the configured mount (as the
// calibrate mount tests render it), played to the daemon as a looping frame directory.
// The daemon converges from the configured mount to the truth, saves it, starts from it
// calibrated after a restart, refuses a corrupted state file in one log line and starts
// uncalibrated, and a mount beyond the bounds makes LDW unavailable ("not calibrated").
//
// The truth is the mean of the rendered frames' own truth columns over the loop (the
// mount plus the vehicle's weaving and bumps, [synth] defaults). Tolerance: the estimate
// is the mean of per-frame solves of the loop's kFrames distinct frames, so its sigma is
// the solver's per-frame sigma (its own report, from the lane messages) over
// sqrt(kFrames); 4 of those. Plus what a last, partial loop can shift the mean by: the
// weaving (heading amplitude A = 2 pi weave / (period v)) and the bumps are sinusoids,
// and a part of a sinusoid of period P averages to at most A P / pi, diluted over the T
// seconds of drive averaged: A P / (pi T).
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Clock = std::chrono::steady_clock;

const std::string kDaemon = CCDLANE_DAEMON, kTool = CCDLANE_TOOL;
constexpr int kFrames = 120;  // 12 s of drive at 10 Hz: two weaving periods
constexpr double kTruePsiOffDeg = 1.5, kTrueThetaOffDeg = -2.0;
constexpr double kConfiguredPsiDeg = 0.0, kConfiguredThetaDeg = 5.0;
constexpr double kFramePeriodS = 0.1;
constexpr int kConvergedFrames = 5 * kFrames;  // at least this many frames averaged
// [synth] defaults: weave 300 mm over 6 s at 25 m/s; pitch bumps 0.4 degrees over 1.3 s.
constexpr double kPi = 3.14159265358979323846;
constexpr double kHeadingAmplitudeDeg = 2 * kPi * 300.0 / (6.0 * 25000.0) * 180.0 / kPi;
double partial_loop_bound_deg(double amplitude_deg, double period_s, std::int64_t frames) {
  return amplitude_deg * period_s / (kPi * static_cast<double>(frames) * kFramePeriodS);
}

struct Received {
  std::vector<lane_estimate_t> lanes;
  std::vector<status_t> statuses;
};

// The half-resolution reference camera with the mount given.
std::string camera_config(double psi_deg, double theta_deg) {
  std::ostringstream t;
  t << "[camera]\nNu = 400\nNv = 300\nUc_mm = 0.0084\nVc_mm = 0.0084\ncx = 200.5\ncy = 150.5\nk_px2 = "
    << -8.3042e-7 * 4 << "\n[attitude]\npsi_deg = " << psi_deg << "\ntheta_deg = " << theta_deg
    << "\n[detection]\nmax_picks = 160\n[synth]\nrate_hz = 10.0\n";
  return t.str();
}

// The mean of a frames.csv column.
double column_mean(const std::string& csv_path, const std::string& column) {
  std::ifstream in(csv_path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  std::stringstream h(line);
  for (std::string cell; std::getline(h, cell, ',');) header.push_back(cell);
  const auto index = static_cast<std::size_t>(std::find(header.begin(), header.end(), column) - header.begin());
  double sum = 0.0;
  int n = 0;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string cell;
    for (std::size_t i = 0; i <= index && std::getline(row, cell, ','); ++i) {
    }
    sum += std::stod(cell);
    ++n;
  }
  return n > 0 ? sum / n : std::nan("");
}

double state_value(const std::string& text, const std::string& key) {
  const auto at = text.find("\n" + key + " = ");
  return at == std::string::npos ? std::nan("") : std::stod(text.substr(at + key.size() + 4));
}

int lines_containing(const std::string& text, const std::string& what) {
  int n = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) n += line.find(what) != std::string::npos;
  return n;
}

class CcdlanedOnlineCalibration : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
    bus_ = std::make_unique<lcm::LCM>(test::kBusUrl);
    ASSERT_TRUE(bus_->good());
    bus_->subscribeFunction(
        "CCDLANE_LANES",
        +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, Received* g) {
          g->lanes.push_back(*m);
        },
        &got_);
    bus_->subscribeFunction(
        "CCDLANE_STATUS",
        +[](const lcm::ReceiveBuffer*, const std::string&, const status_t* m, Received* g) {
          g->statuses.push_back(*m);
        },
        &got_);
    const std::string truth = dir_.write(
        "truth.toml", camera_config(kConfiguredPsiDeg + kTruePsiOffDeg, kConfiguredThetaDeg + kTrueThetaOffDeg));
    frames_ = dir_.file("drive");
    const auto r = test::run_process({kTool, "synth", truth, "--out", frames_, "--frames", std::to_string(kFrames)});
    ASSERT_EQ(r.exit_status, 0) << r.err;
    state_file_ = dir_.file("state/mount-refinement.toml");
    std::filesystem::create_directory(dir_.file("state"));
  }

  // The configured (wrong) mount, the drive looping as fast as it is processed.
  std::string daemon_config(double max_correction_deg = 3.0) {
    std::ostringstream t;
    t << camera_config(kConfiguredPsiDeg, kConfiguredThetaDeg) << "[source]\nkind = \"frames\"\npath = \"" << frames_
      << "\"\nrate_hz = 100\nloop = true\n[calibration]\nonline = true\nframes_needed = " << 2 * kFrames
      << "\nmax_change_deg_per_min = 30\nmax_correction_deg = " << max_correction_deg << "\nsave_period_s = 1\n";
    return dir_.write("daemon.toml", t.str());
  }

  // Runs the daemon (its state directory given as systemd gives it) until `done` says so
  // of the messages so far, or 90 s; then SIGTERM. Returns its stderr.
  std::string run_daemon(const std::string& config, const std::function<bool(const Received&)>& done) {
    got_ = {};
    const std::string err = dir_.file("stderr");
    test::ChildProcess daemon({kDaemon, "--config", config},
                              test::ChildOptions{{"STATE_DIRECTORY=" + dir_.file("state")}, "", err, {}});
    const auto end = Clock::now() + std::chrono::seconds(90);
    while (Clock::now() < end && !done(got_) && !daemon.wait_exit(0)) bus_->handleTimeout(50);
    EXPECT_TRUE(done(got_)) << "timed out; " << test::read_file(err);
    daemon.signal(SIGTERM);
    const auto status = daemon.wait_exit(30'000);
    EXPECT_TRUE(status && WIFEXITED(*status) && WEXITSTATUS(*status) == 0) << test::read_file(err);
    while (bus_->handleTimeout(100) > 0) {
    }
    return test::read_file(err);
  }

  // 4 of the estimate's sigmas: the solver's per-frame sigma (RMS over the ok frames
  // received) over sqrt(kFrames).
  double tolerance(double lane_estimate_t::*sigma) const {
    double sum2 = 0.0;
    int n = 0;
    for (const lane_estimate_t& m : got_.lanes)
      if (m.ok) sum2 += (m.*sigma) * (m.*sigma), ++n;
    return n > 0 ? 4.0 * std::sqrt(sum2 / n) / std::sqrt(static_cast<double>(kFrames)) : 0.0;
  }

  test::TempDir dir_;
  std::unique_ptr<lcm::LCM> bus_;
  Received got_;
  std::string frames_, state_file_;
};

bool converged(const Received& got) {
  if (got.statuses.empty()) return false;
  const status_t& s = got.statuses.back();
  return s.calibration_state == status_t::CALIBRATION_CALIBRATED && s.calibration_frames_total >= kConvergedFrames &&
         std::abs(s.calibration_yaw_deg - s.calibration_yaw_estimate_deg) < 1e-3 &&
         std::abs(s.calibration_pitch_deg - s.calibration_pitch_estimate_deg) < 1e-3;
}

TEST_F(CcdlanedOnlineCalibration, ConvergesToTheTrueMountPersistsItAndRestartsCalibrated) {
  const std::string config = daemon_config();
  const std::string csv = frames_ + "/frames.csv";
  const double true_psi = column_mean(csv, "truth_psi_deg") - kConfiguredPsiDeg;
  const double true_theta = column_mean(csv, "truth_theta_deg") - kConfiguredThetaDeg;

  std::string log = run_daemon(config, converged);
  ASSERT_FALSE(got_.statuses.empty()) << log;
  EXPECT_EQ(got_.statuses.front().calibration_state == status_t::CALIBRATION_CALIBRATED, false)
      << "it starts from the configured mount";
  const status_t& s = got_.statuses.back();
  const double tol_psi = tolerance(&lane_estimate_t::sigma_psi_deg) +
                         partial_loop_bound_deg(kHeadingAmplitudeDeg, 6.0, s.calibration_frames_total);
  const double tol_theta =
      tolerance(&lane_estimate_t::sigma_theta_deg) + partial_loop_bound_deg(0.4, 1.3, s.calibration_frames_total);
  std::cout << "truth yaw " << true_psi << " pitch " << true_theta << "; converged to yaw " << s.calibration_yaw_deg
            << " +- " << s.calibration_yaw_sigma_deg << " pitch " << s.calibration_pitch_deg << " +- "
            << s.calibration_pitch_sigma_deg << " after " << s.calibration_frames_total << " frames; tolerance "
            << tol_psi << " / " << tol_theta << "\n";
  EXPECT_NEAR(s.calibration_yaw_deg, true_psi, tol_psi) << log;
  EXPECT_NEAR(s.calibration_pitch_deg, true_theta, tol_theta) << log;
  EXPECT_DOUBLE_EQ(s.calibration_progress, 1.0);
  EXPECT_GE(lines_containing(log, "mount correction now"), 1) << "applied changes are logged: " << log;
  EXPECT_EQ(s.allocations_since_ready, 0) << "the refinement and its saves allocate nothing";

  // Saved at stop (and periodically), atomically: no temporary left.
  const std::string saved = test::read_file(state_file_);
  ASSERT_FALSE(saved.empty()) << log;
  EXPECT_FALSE(std::filesystem::exists(state_file_ + ".tmp"));
  const double saved_psi = state_value(saved, "applied_psi_deg");
  const double saved_theta = state_value(saved, "applied_theta_deg");
  EXPECT_NEAR(saved_psi, true_psi, tol_psi) << saved;
  EXPECT_NEAR(saved_theta, true_theta, tol_theta) << saved;

  // A restart starts from the saved mount: calibrated in its first status, which comes
  // before frames_needed frames (learning afresh, it would still be calibrating), with the
  // correction on the truth (the new frames refine it further).
  log = run_daemon(config, [](const Received& got) { return !got.statuses.empty(); });
  ASSERT_FALSE(got_.statuses.empty());
  const status_t& first = got_.statuses.front();
  EXPECT_LT(first.frames_processed_total, 2 * kFrames) << "the first status comes early (1 s at 100 fps)";
  EXPECT_EQ(first.calibration_state, status_t::CALIBRATION_CALIBRATED) << log;
  EXPECT_NEAR(first.calibration_yaw_deg, true_psi,
              tol_psi + partial_loop_bound_deg(kHeadingAmplitudeDeg, 6.0, first.calibration_frames_total))
      << log;
  EXPECT_NEAR(first.calibration_pitch_deg, true_theta,
              tol_theta + partial_loop_bound_deg(0.4, 1.3, first.calibration_frames_total))
      << log;
  EXPECT_EQ(lines_containing(log, "learned mount loaded"), 1) << log;
}

TEST_F(CcdlanedOnlineCalibration, ACorruptedStateFileIsOneLogLineAndTheDaemonStartsUncalibrated) {
  const std::string config = daemon_config();
  std::ofstream(state_file_) << "format = 1\nconfigured_psi_deg = 0\nconfigured_theta_deg = 5\nestimate_psi_deg = "
                                "1.5\x01\x02 garbage\n";
  const std::string log = run_daemon(config, [](const Received& got) { return got.statuses.size() >= 2; });
  ASSERT_FALSE(got_.statuses.empty()) << log;
  const status_t& first = got_.statuses.front();
  EXPECT_NE(first.calibration_state, status_t::CALIBRATION_CALIBRATED) << log;
  EXPECT_LT(first.calibration_frames_total, 2 * kFrames) << "learning from the first frame on, not from the file";
  EXPECT_EQ(first.calibration_yaw_deg, 0.0);
  EXPECT_EQ(first.calibration_pitch_deg, 0.0);
  EXPECT_EQ(lines_containing(log, state_file_), 1) << "exactly one line about the file: " << log;
  EXPECT_EQ(lines_containing(log, "not used: estimate_psi_deg is not a number"), 1) << log;
}

TEST_F(CcdlanedOnlineCalibration, AMountBeyondTheBoundsIsOutOfRangeAndLdwNotCalibrated) {
  // The truth is 1.5 degrees of yaw off: beyond a 1 degree bound.
  const std::string config = daemon_config(1.0);
  const std::string log = run_daemon(config, [](const Received& got) {
    return !got.statuses.empty() && got.statuses.back().calibration_state == status_t::CALIBRATION_OUT_OF_RANGE &&
           !got.lanes.empty() && got.lanes.back().ldw_reason == lane_estimate_t::LDW_REASON_NOT_CALIBRATED;
  });
  ASSERT_FALSE(got_.statuses.empty()) << log;
  const status_t& s = got_.statuses.back();
  EXPECT_EQ(s.calibration_state, status_t::CALIBRATION_OUT_OF_RANGE) << log;
  EXPECT_LE(std::abs(s.calibration_yaw_deg), 1.0) << "the correction in use stays within the bound";
  EXPECT_FALSE(got_.lanes.back().ldw_available);
  EXPECT_EQ(lines_containing(log, "out of range"), 1) << log;
  EXPECT_FALSE(std::filesystem::exists(state_file_)) << "an out-of-range mount is not kept";
}

}  // namespace
}  // namespace ccdlane
