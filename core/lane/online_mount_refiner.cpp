// The running mean forgets exponentially once it holds memory_frames frames (weight 1/n
// until then: the plain mean), and its variance follows the same weights (West's
// incremental form), so both cost O(1) per frame and nothing is stored per frame.
#include "core/lane/online_mount_refiner.hpp"

#include <algorithm>
#include <cmath>

namespace ccdlane::calibration {
namespace {

// Before this many frames the spread is too rough to call anything an outlier.
constexpr std::int64_t kFramesBeforeGating = 50;
// A spread floor for the gate: noise-free solves must not lock the mean onto one value.
constexpr double kGateFloorDeg = 0.02;
// A longer gap between samples moves the correction as if only this much time had
// passed: frames resuming after minutes must not bring a jump.
constexpr std::int64_t kMaxStepNs = 1'000'000'000;

double toward(double from, double to, double max_step) { return from + std::clamp(to - from, -max_step, max_step); }

}  // namespace

const char* to_string(OnlineMountState state) {
  switch (state) {
    case OnlineMountState::off: return "off";
    case OnlineMountState::uncalibrated: return "uncalibrated";
    case OnlineMountState::calibrating: return "calibrating";
    case OnlineMountState::calibrated: return "calibrated";
    case OnlineMountState::out_of_range: return "out_of_range";
  }
  return "?";
}

OnlineMountRefiner::OnlineMountRefiner(const OnlineMountOptions& options)
    : options_(options),
      memory_(options.memory_frames > 0 ? options.memory_frames : 10 * std::max(options.frames_needed, 1)) {
  reset();
}

void OnlineMountRefiner::reset() {
  frames_ = 0;
  weight_count_ = 0.0;
  mean_ = {options_.configured_psi_deg, options_.configured_theta_deg};
  var_psi_ = var_theta_ = 0.0;
  applied_ = {};
  last_t_ns_.reset();
}

void OnlineMountRefiner::restore(const LearnedMount& learned) {
  reset();
  frames_ = std::max<std::int64_t>(learned.frames, options_.frames_needed);
  weight_count_ = static_cast<double>(std::min<std::int64_t>(frames_, memory_));
  mean_ = {options_.configured_psi_deg + learned.estimate.psi_deg,
           options_.configured_theta_deg + learned.estimate.theta_deg};
  var_psi_ = learned.spread.psi_deg * learned.spread.psi_deg;
  var_theta_ = learned.spread.theta_deg * learned.spread.theta_deg;
  const double max = options_.max_correction_deg;
  applied_ = {std::clamp(learned.applied.psi_deg, -max, max), std::clamp(learned.applied.theta_deg, -max, max)};
}

bool OnlineMountRefiner::qualifies(const MountSample& s) {
  if (!s.solved || !std::isfinite(s.psi_deg) || !std::isfinite(s.theta_deg)) return ++counts_.unsolved, false;
  if (!(s.speed_kmh >= options_.min_speed_kmh)) return ++counts_.slow, false;
  if (!(std::abs(s.curvature_per_m) <= options_.max_curvature_per_m)) return ++counts_.curved, false;
  if (s.yaw_rate_deg_s && !(std::abs(*s.yaw_rate_deg_s) <= options_.max_yaw_rate_deg_s))
    return ++counts_.turning, false;
  return true;
}

void OnlineMountRefiner::accumulate(double psi_deg, double theta_deg) {
  ++frames_;
  weight_count_ = std::min(weight_count_ + 1.0, static_cast<double>(memory_));
  const double w = 1.0 / weight_count_;
  const double dp = psi_deg - mean_.psi_deg, dt = theta_deg - mean_.theta_deg;
  mean_.psi_deg += w * dp;
  mean_.theta_deg += w * dt;
  var_psi_ = (1.0 - w) * (var_psi_ + w * dp * dp);
  var_theta_ = (1.0 - w) * (var_theta_ + w * dt * dt);
}

bool OnlineMountRefiner::add(const MountSample& s) {
  bool used = false;
  if (qualifies(s)) {
    const double gate_psi = options_.outlier_sigmas * std::max(std::sqrt(var_psi_), kGateFloorDeg);
    const double gate_theta = options_.outlier_sigmas * std::max(std::sqrt(var_theta_), kGateFloorDeg);
    const bool outlier = frames_ >= kFramesBeforeGating && (std::abs(s.psi_deg - mean_.psi_deg) > gate_psi ||
                                                            std::abs(s.theta_deg - mean_.theta_deg) > gate_theta);
    if (!outlier) {
      accumulate(s.psi_deg, s.theta_deg);
      ++counts_.used;
      used = true;
    } else {
      ++counts_.outliers;
    }
  }
  follow(s.t_ns);
  return used;
}

void OnlineMountRefiner::follow(std::int64_t t_ns) {
  const std::int64_t dt_ns = last_t_ns_ ? std::clamp<std::int64_t>(t_ns - *last_t_ns_, 0, kMaxStepNs) : 0;
  if (!last_t_ns_ || t_ns > *last_t_ns_) last_t_ns_ = t_ns;
  if (!established()) return;
  const double step = options_.max_change_deg_per_min / 60.0 * static_cast<double>(dt_ns) * 1e-9;
  const double max = options_.max_correction_deg;
  const MountAngles target = estimate();
  applied_.psi_deg = toward(applied_.psi_deg, std::clamp(target.psi_deg, -max, max), step);
  applied_.theta_deg = toward(applied_.theta_deg, std::clamp(target.theta_deg, -max, max), step);
}

OnlineMountState OnlineMountRefiner::state() const {
  if (frames_ == 0) return OnlineMountState::uncalibrated;
  if (!established()) return OnlineMountState::calibrating;
  const MountAngles e = estimate();
  const double max = options_.max_correction_deg;
  return std::abs(e.psi_deg) > max || std::abs(e.theta_deg) > max ? OnlineMountState::out_of_range
                                                                  : OnlineMountState::calibrated;
}

double OnlineMountRefiner::progress() const {
  return std::min(1.0, static_cast<double>(frames_) / std::max(options_.frames_needed, 1));
}

MountAngles OnlineMountRefiner::estimate() const {
  return {mean_.psi_deg - options_.configured_psi_deg, mean_.theta_deg - options_.configured_theta_deg};
}

MountAngles OnlineMountRefiner::spread() const { return {std::sqrt(var_psi_), std::sqrt(var_theta_)}; }

MountAngles OnlineMountRefiner::sigma() const {
  const double n = std::max(weight_count_, 1.0);
  return {std::sqrt(var_psi_ / n), std::sqrt(var_theta_ / n)};
}

LearnedMount OnlineMountRefiner::learned() const { return {estimate(), applied_, spread(), frames_}; }

OnlineMountStatus OnlineMountRefiner::status() const {
  return {state(), progress(), applied_, estimate(), sigma(), frames_};
}

}  // namespace ccdlane::calibration
