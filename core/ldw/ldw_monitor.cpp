// One frame of lane departure warning: filter, wheels, time to crossing, decision.
#include "core/ldw/ldw_monitor.hpp"

#include "core/geometry/types.hpp"
#include "core/ldw/tlc.hpp"

namespace ccdlane::ldw {

LdwMonitor::LdwMonitor(const LdwConfig& config) : config_(config), filter_(config.filter), warning_(config.warning) {}

void LdwMonitor::reset_mount() {
  reset();
  filter_.reset_mount();
}

void LdwMonitor::reset() {
  filter_.reset();
  warning_.reset();
  last_t_s_.reset();
  result_ = LdwResult{};
  estimate_ = LdwEstimate{};
}

const LdwResult& LdwMonitor::step(const LdwFrameInput& in) {
  const double speed = config_.vehicle.speed_mps(in.speed_mps);
  const double dt = last_t_s_ ? std::max(0.0, in.t_s - *last_t_s_) : 0.0;
  last_t_s_ = in.t_s;
  const LaneState& lane = filter_.step(dt, {speed, in.yaw_rate_radps}, in.measurement);

  LdwResult& r = result_;
  r.lane = lane;
  r.speed_mps = speed;
  r.lateral_velocity_mps = lane.lateral_velocity_mps;
  const LanePose pose{lane.value(kOffset), lane.value(kHeading), lane.value(kCurvature), lane.value(kWidth)};
  const bool have_lane = lane.status != TrackStatus::lost;
  r.dlc = have_lane ? distance_to_line_crossing(pose, config_.vehicle, config_.line_width_mm * 1e-3) : SideDistances{};
  const double v = lane.lateral_velocity_mps, a = lane.lateral_acceleration_mps2;
  r.tlc_left_s = have_lane ? time_to_line_crossing(r.dlc.left_m, v, a) : std::nullopt;
  r.tlc_right_s = have_lane ? time_to_line_crossing(r.dlc.right_m, -v, -a) : std::nullopt;

  LdwInput w;
  w.t_s = in.t_s;
  w.speed_mps = speed;
  w.indicator = in.indicator;
  w.lane_tracked = (lane.status == TrackStatus::tracking || lane.status == TrackStatus::coasting) &&
                   lane.sigma(kOffset) * 1000.0 <= config_.max_offset_sigma_mm;
  w.lane_changed = lane.lane_change != LaneChange::none;
  w.camera_ok = in.camera_ok;
  w.gyro_ok = in.gyro_ok;
  w.vehicle_ok = in.vehicle_ok;
  w.calibrated = in.calibrated;
  w.left = {r.dlc.left_m, v, r.tlc_left_s};
  w.right = {r.dlc.right_m, -v, r.tlc_right_s};
  r.decision = warning_.update(w);
  report(in.indicator);
  return r;
}

void LdwMonitor::report(TurnIndicator indicator) {
  const LdwResult& r = result_;
  LdwEstimate& out = estimate_;
  out.available = r.decision.available;
  out.reason = r.decision.reason;
  out.warning = r.decision.warning;
  out.fired = r.decision.fired;
  out.warnings = r.decision.warnings;
  out.track = r.lane.status;
  out.tracked = r.lane.status != TrackStatus::lost;
  out.dlc_left_mm = r.dlc.left_m * 1e3;
  out.dlc_right_mm = r.dlc.right_m * 1e3;
  out.tlc_left_s = r.tlc_left_s;
  out.tlc_right_s = r.tlc_right_s;
  out.lateral_velocity_mps = r.lateral_velocity_mps;
  out.sigma_lateral_velocity_mps = r.lane.sigma_lateral_velocity_mps;
  out.speed_mps = r.speed_mps;
  out.indicator = indicator;
  const StateVector& x = r.lane.value;
  const StateVector& sd = r.lane.sigma;
  out.offset_mm = x(kOffset) * 1e3;
  out.heading_deg = rad_to_deg(x(kHeading));
  out.curvature_per_m = x(kCurvature);
  out.lane_width_mm = x(kWidth) * 1e3;
  out.pitch_deg = rad_to_deg(x(kPitch));
  out.roll_deg = rad_to_deg(x(kRoll));
  out.heading_bias_deg = rad_to_deg(x(kHeadingBias));
  out.sigma_offset_mm = sd(kOffset) * 1e3;
  out.sigma_heading_deg = rad_to_deg(sd(kHeading));
  out.sigma_curvature_per_m = sd(kCurvature);
  out.sigma_lane_width_mm = sd(kWidth) * 1e3;
  out.sigma_pitch_deg = rad_to_deg(sd(kPitch));
  out.sigma_roll_deg = rad_to_deg(sd(kRoll));
  out.sigma_heading_bias_deg = rad_to_deg(sd(kHeadingBias));
}

}  // namespace ccdlane::ldw
