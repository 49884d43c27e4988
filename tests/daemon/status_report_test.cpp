// Status: per-period counts from totals, rates, texts cut to their reserved size, and a
// status second that allocates nothing.
#include "daemon/status_report.hpp"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "bus/lcm_publisher.hpp"
#include "daemon/allocation_counter.hpp"

namespace ccdlane {
namespace {

StatusInputs inputs_at(std::int64_t uptime_s, std::uint64_t in, std::uint64_t processed, std::uint64_t ok,
                       std::uint64_t dropped) {
  StatusInputs s;
  s.utime = 1'700'000'000'000'000 + uptime_s * 1'000'000;
  s.uptime_us = uptime_s * 1'000'000;
  s.totals.frames_in = in;
  s.totals.frames_processed = processed;
  s.totals.frames_ok = ok;
  s.totals.frames_dropped = dropped;
  s.totals.not_ok_by_reason[static_cast<int>(EstimateFailure::too_few_marks)] = processed - ok;
  s.totals.camera = CameraState::streaming;
  s.totals.ready = true;
  return s;
}

TEST(StatusReport, PeriodCountsAreDifferencesOfTotals) {
  StatusReport report("test-pattern 800x600");
  report.update(inputs_at(1, 30, 29, 29, 1));
  StatusInputs second = inputs_at(2, 60, 58, 54, 2);
  second.latency = LatencySummary{29, 180, 1234, 1500};
  second.gyro = GyroState::stale;
  second.gyro_counters.samples = 200;
  second.gyro_counters.reconnects = 2;
  second.gyro_problem = "no sample for 0.5 s";
  second.totals.source.timeouts = 3;
  second.totals.no_attitude = 7;
  const status_t& m = report.update(second);
  EXPECT_EQ(m.period_us, 1'000'000);
  EXPECT_EQ(m.frames_in, 30);
  EXPECT_EQ(m.frames_processed, 29);
  EXPECT_EQ(m.frames_ok, 25);
  EXPECT_EQ(m.frames_dropped, 1);
  EXPECT_DOUBLE_EQ(m.ok_rate, 25.0 / 29.0);
  EXPECT_EQ(m.frames_in_total, 60);
  EXPECT_EQ(m.frames_dropped_total, 2);
  EXPECT_EQ(m.frames_not_ok_total, 4);
  EXPECT_EQ(m.not_ok_by_reason[lane_estimate_t::REASON_TOO_FEW_MARKS], 4);
  EXPECT_EQ(m.latency_p50_us, 180);
  EXPECT_EQ(m.latency_p99_us, 1234);
  EXPECT_EQ(m.latency_max_us, 1500);
  EXPECT_EQ(m.camera_state, status_t::CAMERA_STREAMING);
  EXPECT_EQ(m.camera, "test-pattern 800x600");
  EXPECT_EQ(m.gyro_state, status_t::GYRO_STALE);
  EXPECT_EQ(m.gyro_problem, "no sample for 0.5 s");
  EXPECT_EQ(m.gyro_samples_total, 200);
  EXPECT_EQ(m.gyro_reconnects_total, 2);
  EXPECT_EQ(m.source_timeouts_total, 3);
  EXPECT_EQ(m.no_attitude_total, 7);
  EXPECT_EQ(m.ready, 1);

  char line[256];
  report.summary_line(line, sizeof line);
  EXPECT_STREQ(line, "streaming 29.0 fps, 86% ok, 2 dropped, p99 1.2 ms, gyro stale (2 reconnects), 0 allocations");
}

TEST(StatusReport, NothingProcessedMeansNoRateAndTheProblemIsShown) {
  StatusReport report("v4l2:/dev/video0");
  StatusInputs s = inputs_at(1, 0, 0, 0, 0);
  s.totals.camera = CameraState::stalled;
  s.camera_problem = "no frame for 2.0 s";
  const status_t& m = report.update(s);
  EXPECT_TRUE(std::isnan(m.ok_rate));
  EXPECT_EQ(m.latency_samples, 0);
  char line[256];
  report.summary_line(line, sizeof line);
  EXPECT_STREQ(line,
               "stalled 0.0 fps, 0% ok, 0 dropped, p99 0.0 ms, gyro none, 0 allocations; camera: no frame for 2.0 s");
}

TEST(StatusReport, TextsAreCutToTheirReservedSizeWithoutAllocating) {
  StatusReport report(std::string(500, 'c'));
  EXPECT_EQ(report.message().camera.size(), kStatusTextMax);
  const std::string long_problem(1000, 'p');
  StatusInputs s = inputs_at(1, 10, 10, 10, 0);
  s.camera_problem = long_problem.c_str();
  s.gyro_problem = long_problem.c_str();
  allocation_counter::start_counting();
  const status_t& m = report.update(s);
  char line[256];
  report.summary_line(line, sizeof line);
  EXPECT_EQ(allocation_counter::count(), 0u);
  allocation_counter::stop_counting();
  EXPECT_EQ(m.camera_problem.size(), kStatusTextMax);
  EXPECT_EQ(m.gyro_problem.size(), kStatusTextMax);
}

TEST(StatusReport, TheOnlineCalibrationIsReported) {
  StatusReport report("test-pattern 800x600");
  EXPECT_EQ(report.update(inputs_at(1, 30, 30, 30, 0)).calibration_state, status_t::CALIBRATION_OFF);
  StatusInputs in = inputs_at(2, 60, 60, 60, 0);
  in.calibration.state = calibration::OnlineMountState::calibrating;
  in.calibration.progress = 0.25;
  in.calibration.applied = {0.5, -0.25};
  in.calibration.estimate = {1.5, -2.0};
  in.calibration.sigma = {0.03, 0.01};
  in.calibration.frames = 225;
  const status_t& m = report.update(in);
  EXPECT_EQ(m.calibration_state, status_t::CALIBRATION_CALIBRATING);
  EXPECT_EQ(m.calibration_progress, 0.25);
  EXPECT_EQ(m.calibration_yaw_deg, 0.5);
  EXPECT_EQ(m.calibration_pitch_deg, -0.25);
  EXPECT_EQ(m.calibration_yaw_estimate_deg, 1.5);
  EXPECT_EQ(m.calibration_pitch_estimate_deg, -2.0);
  EXPECT_EQ(m.calibration_yaw_sigma_deg, 0.03);
  EXPECT_EQ(m.calibration_pitch_sigma_deg, 0.01);
  EXPECT_EQ(m.calibration_frames_total, 225);
}

}  // namespace
}  // namespace ccdlane
