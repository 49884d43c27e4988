// The warning decision. A side warns once per departure: it must be armed (its wheel seen
// well inside since the last warning), approaching, within the threshold and not
// suppressed; warning disarms it. Unavailability disarms both sides, so that LDW coming
// back (speed, lane found) never warns for a wheel already near the line.
#include "core/ldw/ldw_warning.hpp"

#include <algorithm>
#include <cstring>

namespace ccdlane::ldw {

const char* to_string(Side s) {
  switch (s) {
    case Side::none: return "none";
    case Side::left: return "left";
    case Side::right: return "right";
  }
  return "?";
}

const char* to_string(Availability a) {
  switch (a) {
    case Availability::none: return "none";
    case Availability::camera_fault: return "camera_fault";
    case Availability::gyro_fault: return "gyro_fault";
    case Availability::not_calibrated: return "not_calibrated";
    case Availability::no_lane: return "no_lane";
    case Availability::too_slow: return "too_slow";
    case Availability::vehicle_fault: return "vehicle_fault";
  }
  return "?";
}

LdwWarning::LdwWarning(const LdwWarningConfig& config) : config_(config) { reset(); }

void LdwWarning::disarm(SideState& side, double dlc_m) const {
  // Already disarmed (say warned at 0.47 m, then a frame without a lane): the level it
  // must get back to stays, or the same departure would be warned twice.
  const double kept = side.armed ? 0.0 : side.arm_at_mm;
  side.armed = false;
  side.arm_at_mm = std::max({config_.rearm_mm, dlc_m * 1000.0 + config_.rearm_margin_mm, kept});
}

void LdwWarning::reset() {
  left_ = right_ = SideState{};
  left_.arm_at_mm = right_.arm_at_mm = config_.rearm_mm;
  speed_ok_ = false;
  warning_until_s_ = -1e300;
  warning_side_ = Side::none;
  out_ = LdwOutput{};
}

double LdwWarning::threshold_mm(double approach_mps) const {
  const double latest_threshold = config_.earliest_warning_mm - config_.earliest_margin_mm;
  return std::clamp(approach_mps * config_.tlc_threshold_s * 1000.0, config_.min_threshold_mm,
                    std::max(config_.min_threshold_mm, latest_threshold));
}

bool LdwWarning::side_update(SideState& side, const LdwSideInput& in, bool indicator_on, double t_s, double& threshold,
                             bool& suppressed) {
  if (side.indicator_on && !indicator_on) side.indicator_off_at_s = t_s;
  side.indicator_on = indicator_on;
  suppressed = indicator_on || t_s - side.indicator_off_at_s < config_.indicator_hold_s;
  const double dlc_mm = in.dlc_m * 1000.0;
  threshold = threshold_mm(in.approach_mps);
  if (dlc_mm >= side.arm_at_mm) side.armed = true;
  const bool departing =
      in.approach_mps >= config_.min_approach_mps && dlc_mm <= threshold && dlc_mm >= config_.latest_warning_mm;
  if (!departing || !side.armed) return false;
  // A departure the driver signalled is used up as well: no warning for it later.
  disarm(side, in.dlc_m);
  return !suppressed;
}

const LdwOutput& LdwWarning::update(const LdwInput& in) {
  LdwOutput& o = out_;
  o.fired = Side::none;
  const double speed_kmh = in.speed_mps * 3.6;
  if (speed_kmh < config_.min_speed_kmh)
    speed_ok_ = false;
  else if (speed_kmh >= config_.min_speed_kmh + config_.speed_hysteresis_kmh)
    speed_ok_ = true;

  o.reason = !in.camera_ok      ? Availability::camera_fault
             : !in.gyro_ok      ? Availability::gyro_fault
             : !in.vehicle_ok   ? Availability::vehicle_fault
             : !in.calibrated   ? Availability::not_calibrated
             : !in.lane_tracked ? Availability::no_lane
             : !speed_ok_       ? Availability::too_slow
                                : Availability::none;
  o.available = o.reason == Availability::none;
  if (in.lane_changed) {  // a new lane: its wheels must first be seen inside
    disarm(left_, 0.0);
    disarm(right_, 0.0);
  }

  const bool hazard = in.indicator == TurnIndicator::both;
  const bool left_on = hazard || in.indicator == TurnIndicator::left;
  const bool right_on = hazard || in.indicator == TurnIndicator::right;
  if (!o.available) {
    // Keep the indicators' timing; disarm, so a wheel already near the line is not warned.
    bool unused = false;
    double unused_threshold = 0.0;
    side_update(left_, in.left, left_on, in.t_s, unused_threshold, unused);
    side_update(right_, in.right, right_on, in.t_s, unused_threshold, unused);
    disarm(left_, 0.0);
    disarm(right_, 0.0);
    o.suppressed_left = o.suppressed_right = false;
  } else {
    const bool fire_left = side_update(left_, in.left, left_on, in.t_s, o.threshold_left_mm, o.suppressed_left);
    const bool fire_right = side_update(right_, in.right, right_on, in.t_s, o.threshold_right_mm, o.suppressed_right);
    // Both at once cannot be a departure of a rigid vehicle; the nearer line wins.
    if (fire_left && (!fire_right || in.left.dlc_m <= in.right.dlc_m))
      o.fired = Side::left;
    else if (fire_right)
      o.fired = Side::right;
  }
  if (o.fired != Side::none) {
    ++o.warnings;
    warning_side_ = o.fired;
    warning_until_s_ = in.t_s + config_.warning_duration_s;
  }
  o.warning = o.available && in.t_s < warning_until_s_ ? warning_side_ : Side::none;
  return o;
}

}  // namespace ccdlane::ldw
