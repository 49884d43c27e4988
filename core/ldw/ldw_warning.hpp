// The lane departure warning decision (ISO 17361, UN R130): when to warn, on which side,
// when not to (too slow, indicator, no confident lane, faults), and whether LDW is
// available at all, for the driver's display.
#pragma once

#include <cstdint>
#include <optional>

#include "base/turn_indicator.hpp"

namespace ccdlane::ldw {

enum class Side : std::uint8_t { none, left, right };
const char* to_string(Side s);  // "none", "left", "right"

// As a CAN gateway reports it (base/turn_indicator.hpp: the drivers read it too).
using TurnIndicator = ccdlane::TurnIndicator;
using ccdlane::to_string;
using ccdlane::turn_indicator_from_string;

// Why LDW is not available; `none` when it is. Listed in order of precedence (the first
// that applies is reported), but for vehicle_fault, which comes after gyro_fault: it was
// added last, and its value is on the bus (lane_estimate_t.LDW_REASON_*).
enum class Availability : std::uint8_t {
  none,            // available
  camera_fault,    // no frames (the camera stalled or failed)
  gyro_fault,      // the gyro is configured and not delivering
  not_calibrated,  // the camera's mounting is not known well enough
  no_lane,         // the lane is not confidently tracked
  too_slow,        // below the minimum speed
  vehicle_fault,   // the vehicle's gateway sends only refused states, or stopped sending
};
const char* to_string(Availability a);  // the names above

struct LdwWarningConfig {
  double min_speed_kmh = 60.0;        // below: not available (too_slow)
  double speed_hysteresis_kmh = 2.0;  // available again at min_speed + this
  double indicator_hold_s = 2.0;      // suppression on a side lasts this long after its indicator
  // The warning zone, as the front wheel's DLC (+ inside the line's inner edge).
  double earliest_warning_mm = 750.0;  // ISO 17361: not while the wheel is farther inside
  double latest_warning_mm = -300.0;   //   and before it is this far beyond
  // The threshold: warn when DLC <= clamp(approach_speed * tlc_threshold_s,
  // min_threshold_mm, earliest_warning_mm - earliest_margin_mm), approaching. Slow
  // drifts are warned near the line (min_threshold_mm), fast ones tlc_threshold_s before
  // it, never earlier than the margin inside the earliest line (room for the DLC's
  // error and a frame's latency).
  double tlc_threshold_s = 0.5;
  double min_threshold_mm = 100.0;
  double earliest_margin_mm = 150.0;
  double min_approach_mps = 0.03;  // slower is "not approaching" (the filter's noise)
  // A side re-arms once its wheel is back inside, at least rearm_mm and at least
  // rearm_margin_mm farther in than where it last warned (or was disarmed).
  double rearm_mm = 400.0;
  double rearm_margin_mm = 200.0;
  double warning_duration_s = 1.0;  // how long `warning` stays set after it fires

  bool operator==(const LdwWarningConfig&) const = default;
};

struct LdwSideInput {
  double dlc_m = 0.0;           // the front wheel on this side, + inside
  double approach_mps = 0.0;    // lateral velocity toward this side's line
  std::optional<double> tlc_s;  // for the record; the decision uses DLC and approach
};

struct LdwInput {
  double t_s = 0.0;  // any monotonic time, seconds
  double speed_mps = 0.0;
  TurnIndicator indicator = TurnIndicator::none;
  bool lane_tracked = false;  // the lane filter is confident (see LdwMonitor)
  bool lane_changed = false;  // the filter re-associated to a neighbour lane this frame
  bool camera_ok = true;
  bool gyro_ok = true;
  bool vehicle_ok = true;
  bool calibrated = true;
  LdwSideInput left, right;
};

struct LdwOutput {
  bool available = false;
  Availability reason = Availability::too_slow;
  Side warning = Side::none;                                 // set for warning_duration_s from a departure's warning
  Side fired = Side::none;                                   // the side whose warning started at this input, if any
  bool suppressed_left = false, suppressed_right = false;    // by the indicator
  double threshold_left_mm = 0.0, threshold_right_mm = 0.0;  // this input's thresholds
  std::uint32_t warnings = 0;                                // warnings fired since construction
};

class LdwWarning {
 public:
  explicit LdwWarning(const LdwWarningConfig& config = {});
  void reset();
  const LdwOutput& update(const LdwInput& in);
  const LdwOutput& output() const { return out_; }
  // Where the warning threshold lies (DLC, mm) for a wheel approaching at this speed.
  double threshold_mm(double approach_mps) const;

 private:
  struct SideState {
    bool armed = false;
    double arm_at_mm = 0.0;              // DLC at which it arms again
    double indicator_off_at_s = -1e300;  // when the indicator toward this side last went off
    bool indicator_on = false;
  };
  void disarm(SideState& side, double dlc_m) const;
  bool side_update(SideState& side, const LdwSideInput& in, bool indicator_on, double t_s, double& threshold_mm,
                   bool& suppressed);

  LdwWarningConfig config_;
  SideState left_, right_;
  bool speed_ok_ = false;
  double warning_until_s_ = -1e300;
  Side warning_side_ = Side::none;
  LdwOutput out_;
};

}  // namespace ccdlane::ldw
