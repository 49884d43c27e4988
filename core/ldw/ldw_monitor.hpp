// Lane departure warning for one camera, frame by frame: the lane filter, the front
// wheels' DLC and TLC, and the warning decision, in the order the daemon and replay
// both run them (so they give the same warnings on the same recording).
#pragma once

#include <cstdint>
#include <optional>

#include "core/ldw/lane_filter.hpp"
#include "core/ldw/ldw_warning.hpp"
#include "core/ldw/vehicle.hpp"

namespace ccdlane::ldw {

struct LdwConfig {
  VehicleConfig vehicle;
  LaneFilterConfig filter;
  LdwWarningConfig warning;
  double line_width_mm = 120.0;        // painted lines: DLC is to their inner edge
  double max_offset_sigma_mm = 150.0;  // a lane whose offset is less certain is not "tracked"

  bool operator==(const LdwConfig&) const = default;
};

struct LdwFrameInput {
  double t_s = 0.0;                      // the frame's time (monotonic), seconds
  std::optional<double> speed_mps;       // empty: [vehicle] speed_kmh
  std::optional<double> yaw_rate_radps;  // + turning left; empty: no gyro rate
  TurnIndicator indicator = TurnIndicator::none;
  const LaneMeasurement* measurement = nullptr;  // null: no usable solve this frame
  bool camera_ok = true;
  bool gyro_ok = true;
  bool vehicle_ok = true;
  bool calibrated = true;
};

struct LdwResult {
  LdwOutput decision;
  LaneState lane;
  SideDistances dlc;                 // metres, + inside (meaningful while the lane is tracked)
  std::optional<double> tlc_left_s;  // empty when not approaching that line
  std::optional<double> tlc_right_s;
  double lateral_velocity_mps = 0.0;  // + toward the left
  double speed_mps = 0.0;             // the speed used
};

// The lane departure warning at this frame as the per-frame result reports it
// (interfaces.md "Per-frame result", `ldw`): the decision, each front wheel's DLC and TLC,
// and the lane filter's state with sigmas, in the result's units. The estimate's `ldw`
// is this, as the monitor made it.
struct LdwEstimate {
  bool available = false;
  Availability reason = Availability::no_lane;  // none when available
  Side warning = Side::none;                    // set for [ldw] warning_duration_s from a departure's warning
  Side fired = Side::none;                      // the side whose warning started at this frame
  std::uint32_t warnings = 0;                   // warnings fired since start
  bool tracked = false;                         // the filter has a lane (status not lost): DLC and state meaningful
  TrackStatus track = TrackStatus::lost;
  double dlc_left_mm = 0.0, dlc_right_mm = 0.0;   // front wheel's outer edge to the line's inner edge, + inside
  std::optional<double> tlc_left_s, tlc_right_s;  // empty when not approaching that line
  double lateral_velocity_mps = 0.0;              // + toward the left
  double speed_mps = 0.0;                         // the speed used (the input's, or [vehicle] speed_kmh)
  TurnIndicator indicator = TurnIndicator::none;
  // The filtered lane state, SI-derived units as in the per-frame result; sigmas are NaN
  // where the state is not estimated (roll with a gyro).
  double offset_mm = 0.0, heading_deg = 0.0, curvature_per_m = 0.0, lane_width_mm = 0.0;
  double pitch_deg = 0.0, roll_deg = 0.0;
  double heading_bias_deg = 0.0;  // the mount's yaw as the heading reads it (lane_filter.hpp)
  double sigma_offset_mm = 0.0, sigma_heading_deg = 0.0, sigma_curvature_per_m = 0.0, sigma_lane_width_mm = 0.0;
  double sigma_pitch_deg = 0.0, sigma_roll_deg = 0.0, sigma_heading_bias_deg = 0.0;
  double sigma_lateral_velocity_mps = 0.0;
};

class LdwMonitor {
 public:
  explicit LdwMonitor(const LdwConfig& config = {});
  // Forgets the track and the warning's state; what the filter learnt of the mount's
  // heading bias is kept (lane_filter.hpp).
  void reset();
  // And that too: another run, another mount.
  void reset_mount();
  // One frame, in time order. Allocation-free.
  const LdwResult& step(const LdwFrameInput& in);
  const LdwResult& result() const { return result_; }
  // The last step's result in the per-frame result's terms: what the estimate reports.
  const LdwEstimate& estimate() const { return estimate_; }
  const LaneFilter& filter() const { return filter_; }
  const LdwConfig& config() const { return config_; }

 private:
  LdwConfig config_;
  LaneFilter filter_;
  LdwWarning warning_;
  void report(TurnIndicator indicator);

  std::optional<double> last_t_s_;
  LdwResult result_;
  LdwEstimate estimate_;
};

}  // namespace ccdlane::ldw
