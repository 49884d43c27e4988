// The vehicle's front wheels relative to the lane lines: the [vehicle] table and the
// distance to line crossing (DLC) of each front wheel, from the filtered lane state.
#pragma once

#include <optional>

namespace ccdlane::ldw {

// The [vehicle] table. Keep exactly these key names: scenario files and other programs
// use them.
struct VehicleConfig {
  double speed_kmh = 72.0;                       // used when no speed input arrives
  double width_mm = 1800.0;                      // between the outer edges of the front wheels
  double front_axle_behind_camera_mm = -1000.0;  // negative: the axle is ahead of the camera
  double camera_left_of_centre_mm = 0.0;         // negative: right of the vehicle's centre line

  // The speed driven: the vehicle's input when there is one, else speed_kmh.
  double speed_mps(const std::optional<double>& input_mps) const { return input_mps.value_or(configured_speed_mps()); }
  double configured_speed_mps() const { return speed_kmh / 3.6; }

  bool operator==(const VehicleConfig&) const = default;
};

// Where the vehicle is in its lane, as the lane filter estimates it (SI units).
//   offset: the camera's lateral position from the lane centre, positive left;
//   heading: the vehicle's direction relative to the lane's tangent, positive left;
//   curvature: the lane's, positive when it bends to the left;
//   width: between the two lines' centres.
struct LanePose {
  double offset_m = 0.0;
  double heading_rad = 0.0;
  double curvature_per_m = 0.0;
  double width_m = 3.75;
};

// Distance to line crossing per side: from the front wheel's outer edge to the inner
// edge of the own lane's line on that side, in metres. Positive while the wheel is
// inside the lane, zero on the edge, negative beyond it.
struct SideDistances {
  double left_m = 0.0;
  double right_m = 0.0;
};

// The lateral position (from the lane centre, positive left) of a point of the vehicle
// `ahead_m` in front of the camera and `left_m` to its left, to second order in heading
// and curvature: the lane bends away by curvature * ahead^2 / 2 at that distance,
// whether the point is ahead of the camera or behind it.
double lateral_position_in_lane_m(const LanePose& pose, double ahead_m, double left_m);

// DLC of each front wheel. `line_width_m`: the painted line's width (the solve finds the
// lines' centres; the wheel crosses the line at its inner edge).
SideDistances distance_to_line_crossing(const LanePose& pose, const VehicleConfig& vehicle, double line_width_m);

}  // namespace ccdlane::ldw
