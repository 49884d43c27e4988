// Lane departure warning for one camera, frame by frame: the lane filter, the front
// wheels' DLC and TLC, and the warning decision, in the order the daemon and replay
// both run them (so they give the same warnings on the same recording).
#pragma once

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

class LdwMonitor {
 public:
  explicit LdwMonitor(const LdwConfig& config = {});
  void reset();
  // One frame, in time order. Allocation-free.
  const LdwResult& step(const LdwFrameInput& in);
  const LdwResult& result() const { return result_; }
  const LaneFilter& filter() const { return filter_; }
  const LdwConfig& config() const { return config_; }

 private:
  LdwConfig config_;
  LaneFilter filter_;
  LdwWarning warning_;
  std::optional<double> last_t_s_;
  LdwResult result_;
};

}  // namespace ccdlane::ldw
