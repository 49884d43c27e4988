// ccdlaned's side of the online mount refinement, which the lane estimator runs as a stage
// of its own (core/lane/mount_refinement.hpp): this finds and loads the state file the
// estimator starts from, takes the stage's result after each frame, and on the status
// thread reports it, logs its changes (rate-limited) and keeps it in the state file.
// The two threads share one snapshot under a mutex the processing thread only ever
// try-locks, so the real-time path never waits.
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>

#include "app/config.hpp"
#include "core/lane/lane_estimator_options.hpp"
#include "core/lane/mount_refinement.hpp"
#include "core/lane/online_mount_refiner.hpp"

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

  // Start-up: turns the estimator's online refinement on in `options`, to start from the
  // mount loaded (leaves them as they are when not enabled).
  void configure(LaneEstimatorOptions& options) const;

  // Processing thread, after each frame's estimate: the refinement stage's result, for
  // the status thread. No allocation, no waiting.
  void share(const MountRefinementResult& result);

  // Status thread.
  calibration::OnlineMountStatus status() const;
  // Once a second: logs state changes and the correction's moves, saves every
  // save_period_s while the estimate is calibrated and has changed. No allocation.
  void tick(std::int64_t now_ns);
  // At stop, after the processing thread has ended: the last save.
  void stop();

 private:
  void load(calibration::OnlineMountRefiner& start);
  void save(const calibration::LearnedMount& learned);
  void log_changes(const calibration::OnlineMountStatus& s, std::int64_t now_ns);

  bool enabled_ = false;
  calibration::OnlineMountOptions options_;
  std::int64_t save_period_ns_ = 0;
  std::string path_;
  std::optional<calibration::LearnedMount> loaded_;  // from the state file

  MountRefinementResult latest_;  // the processing thread's: the stage's last result

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
