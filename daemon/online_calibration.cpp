// The processing thread publishes its snapshot only when the mutex is free: a frame whose
// snapshot is skipped is followed by another a frame later, while a processing thread
// that waited on the status thread would be a real-time thread blocked by a normal one.
#include "daemon/online_calibration.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "base/log.hpp"
#include "base/regular_file.hpp"
#include "daemon/mount_state_file.hpp"

namespace ccdlane {
namespace {

using calibration::LearnedMount;
using calibration::OnlineMountState;
using calibration::OnlineMountStatus;

constexpr std::size_t kMaxStateFileBytes = 4096;

// [calibration] state_file, else the first directory of $STATE_DIRECTORY (systemd's
// StateDirectory=; it may list several, separated by ':'); "" when neither is set.
std::string state_file_path(const Config& config) {
  if (!config.calibration.state_file.empty()) return config.calibration.state_file;
  const char* dirs = std::getenv("STATE_DIRECTORY");
  if (!dirs || !*dirs) return "";
  std::string dir(dirs);
  dir = dir.substr(0, dir.find(':'));
  return dir + "/" + kMountStateFileName;
}

}  // namespace

OnlineCalibration::OnlineCalibration(const Config& config)
    : enabled_(config.calibration.online),
      options_(config.online_mount_options()),
      save_period_ns_(static_cast<std::int64_t>(config.calibration.save_period_s * 1e9)) {
  if (!enabled_) return;
  path_ = state_file_path(config);
  // Where the estimator's stage will start, to report before its first frame.
  calibration::OnlineMountRefiner start(options_);
  load(start);
  latest_.status = shared_status_ = start.status();
  latest_.learned = shared_learned_ = start.learned();
  logged_state_ = shared_status_.state;
  logged_applied_ = shared_status_.applied;
  saved_frames_ = shared_learned_.frames;
}

void OnlineCalibration::load(calibration::OnlineMountRefiner& start) {
  if (path_.empty()) {
    log_line(LogLevel::notice, "calibration",
             "no [calibration] state_file and no $STATE_DIRECTORY: the mount learned online is not kept across "
             "restarts; starting uncalibrated");
    return;
  }
  // A regular file only, opened without blocking: a FIFO or "/" is no state file.
  std::string text;
  const int rc = read_regular_file(path_, kMaxStateFileBytes, text);
  if (rc == -ENOENT) {
    log_line(LogLevel::info, "calibration", "%s: no mount learned yet; starting uncalibrated", path_.c_str());
    return;
  }
  std::string why;
  LearnedMount learned;
  if (rc == -EFBIG)
    why = "larger than " + std::to_string(kMaxStateFileBytes) + " bytes: not a state file";
  else if (rc == -EINVAL)
    why = "not a regular file: not a state file";
  else if (rc < 0)
    why = std::string("cannot be read: ") + regular_file_error(rc);
  else if (text.find('\0') != std::string::npos)
    why = "holds NUL bytes: not a state file";
  else
    why = parse_mount_state(text, options_, learned);
  if (!why.empty()) {
    log_line(LogLevel::warning, "calibration", "%s: not used: %s; starting uncalibrated", path_.c_str(), why.c_str());
    return;
  }
  loaded_ = learned;
  start.restore(learned);
  log_line(LogLevel::info, "calibration",
           "%s: learned mount loaded: correction yaw %+.3f pitch %+.3f deg (estimate %+.3f %+.3f, %lld frames); %s",
           path_.c_str(), learned.applied.psi_deg, learned.applied.theta_deg, learned.estimate.psi_deg,
           learned.estimate.theta_deg, static_cast<long long>(learned.frames), to_string(start.state()));
}

void OnlineCalibration::configure(LaneEstimatorOptions& options) const {
  if (!enabled_) return;
  options.online_mount = options_;
  options.learned_mount = loaded_;
}

void OnlineCalibration::share(const MountRefinementResult& result) {
  if (!enabled_) return;
  latest_ = result;
  std::unique_lock lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  shared_status_ = result.status;
  shared_learned_ = result.learned;
}

OnlineMountStatus OnlineCalibration::status() const {
  std::lock_guard lock(mutex_);
  return shared_status_;
}

void OnlineCalibration::log_changes(const OnlineMountStatus& s, std::int64_t now_ns) {
  if (s.state != logged_state_) {
    if (s.state == OnlineMountState::out_of_range)
      log_line(LogLevel::warning, "calibration",
               "out of range: the mount learned is yaw %+.3f pitch %+.3f deg off [attitude], beyond "
               "max_correction_deg %.3f; lane departure warning unavailable (not calibrated)",
               s.estimate.psi_deg, s.estimate.theta_deg, options_.max_correction_deg);
    else
      log_line(LogLevel::info, "calibration",
               "%s -> %s (estimate yaw %+.3f +- %.3f, pitch %+.3f +- %.3f deg, %lld frames)", to_string(logged_state_),
               to_string(s.state), s.estimate.psi_deg, s.sigma.psi_deg, s.estimate.theta_deg, s.sigma.theta_deg,
               static_cast<long long>(s.frames));
    logged_state_ = s.state;
  }
  const bool moved = std::abs(s.applied.psi_deg - logged_applied_.psi_deg) >= kLoggedChangeDeg ||
                     std::abs(s.applied.theta_deg - logged_applied_.theta_deg) >= kLoggedChangeDeg;
  if (moved && now_ns - logged_change_ns_ >= kChangeLogPeriodNs) {
    log_line(LogLevel::info, "calibration",
             "mount correction now yaw %+.3f pitch %+.3f deg (was %+.3f %+.3f; estimate %+.3f +- %.3f, %+.3f +- %.3f)",
             s.applied.psi_deg, s.applied.theta_deg, logged_applied_.psi_deg, logged_applied_.theta_deg,
             s.estimate.psi_deg, s.sigma.psi_deg, s.estimate.theta_deg, s.sigma.theta_deg);
    logged_applied_ = s.applied;
    logged_change_ns_ = now_ns;
  }
}

void OnlineCalibration::tick(std::int64_t now_ns) {
  if (!enabled_) return;
  OnlineMountStatus s;
  LearnedMount learned;
  {
    std::lock_guard lock(mutex_);
    s = shared_status_;
    learned = shared_learned_;
  }
  log_changes(s, now_ns);
  if (saved_ns_ == 0) saved_ns_ = now_ns;  // the first period counts from the first tick
  if (s.state == OnlineMountState::calibrated && learned.frames != saved_frames_ &&
      now_ns - saved_ns_ >= save_period_ns_) {
    save(learned);
    saved_ns_ = now_ns;
  }
}

void OnlineCalibration::stop() {
  if (!enabled_) return;
  // The processing thread has ended: its last result is ours now, complete to the last frame.
  const OnlineMountStatus& s = latest_.status;
  log_changes(s, logged_change_ns_ + kChangeLogPeriodNs);
  if (s.state == OnlineMountState::calibrated && latest_.learned.frames != saved_frames_) save(latest_.learned);
}

void OnlineCalibration::save(const LearnedMount& learned) {
  if (path_.empty()) return;
  char text[1024];
  const std::size_t n = format_mount_state(learned, options_, text, sizeof text);
  const FileWriteError e = n ? write_file_atomically(path_.c_str(), text, n) : FileWriteError{"format", 0};
  if (e) {
    if (!save_failed_said_)
      log_line(LogLevel::warning, "calibration",
               "%s: cannot save the learned mount (%s: %s); further failures not logged", path_.c_str(), e.step,
               std::strerror(e.error));
    save_failed_said_ = true;
    return;
  }
  saved_frames_ = learned.frames;
}

}  // namespace ccdlane
