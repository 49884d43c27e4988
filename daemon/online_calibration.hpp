// ccdlaned's online mount refinement: the processing thread feeds every frame's solve to
// an OnlineMountRefiner and hands the correction in use to the estimator; the status
// thread reports it, logs its changes (rate-limited) and keeps it in the state file.
// The two threads share one snapshot under a mutex the processing thread only ever
// try-locks, so the real-time path never waits.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

#include "app/config.hpp"
#include "core/lane/online_mount_refiner.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator.hpp"

namespace ccdlane {

class OnlineCalibration {
 public:
  static constexpr std::int64_t kChangeLogPeriodNs = 10'000'000'000;  // at most one "correction now" line
  static constexpr double kLoggedChangeDeg = 0.01;                    // smaller changes go unsaid

  // With [calibration] online: the state file is found ([calibration] state_file, else
  // $STATE_DIRECTORY) and loaded; a missing one says so in one line, one that cannot be
  // used says why in one line, and either way the refinement starts uncalibrated.
  // Start-up only: may allocate, never throws for the file.
  explicit OnlineCalibration(const Config& config);

  bool enabled() const { return enabled_; }
  const std::string& state_file() const { return path_; }  // "" when not kept

  // Processing thread, around each frame's estimate. No allocation, no waiting.
  void before_frame(LaneEstimator& estimator, VehicleInputs& vehicle);
  void after_frame(const LaneEstimate& estimate, const VehicleInputs& vehicle);

  // Status thread.
  calibration::OnlineMountStatus status() const;
  // Once a second: logs state changes and the correction's moves, saves every
  // save_period_s while the estimate is calibrated and has changed. No allocation.
  void tick(std::int64_t now_ns);
  // At stop, after the processing thread has ended: the last save.
  void stop();

 private:
  void load();
  void save(const calibration::LearnedMount& learned);
  void log_changes(const calibration::OnlineMountStatus& s, std::int64_t now_ns);

  bool enabled_ = false;
  calibration::OnlineMountOptions options_;
  std::int64_t save_period_ns_ = 0;
  std::string path_;

  calibration::OnlineMountRefiner refiner_;  // the processing thread's

  mutable std::mutex mutex_;  // guards the two below
  calibration::OnlineMountStatus shared_status_;
  calibration::LearnedMount shared_learned_;

  // The status thread's.
  calibration::OnlineMountState logged_state_ = calibration::OnlineMountState::off;
  calibration::MountAngles logged_applied_;
  std::int64_t logged_change_ns_ = 0;
  std::int64_t saved_ns_ = 0;
  std::int64_t saved_frames_ = -1;
  bool save_failed_said_ = false;
};

}  // namespace ccdlane
