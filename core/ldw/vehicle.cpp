// Front-wheel geometry in the lane.
#include "core/ldw/vehicle.hpp"

#include <cmath>

namespace ccdlane::ldw {

double lateral_position_in_lane_m(const LanePose& pose, double ahead_m, double left_m) {
  const double s = std::sin(pose.heading_rad), c = std::cos(pose.heading_rad);
  return pose.offset_m + ahead_m * s + left_m * c - 0.5 * pose.curvature_per_m * ahead_m * ahead_m;
}

SideDistances distance_to_line_crossing(const LanePose& pose, const VehicleConfig& vehicle, double line_width_m) {
  const double ahead = -vehicle.front_axle_behind_camera_mm * 1e-3;
  const double half_width = 0.5 * vehicle.width_mm * 1e-3;
  const double centre_left =
      -vehicle.camera_left_of_centre_mm * 1e-3;  // the vehicle's centre line, seen from the camera
  const double inner_edge = 0.5 * (pose.width_m - line_width_m);
  const double left_wheel = lateral_position_in_lane_m(pose, ahead, centre_left + half_width);
  const double right_wheel = lateral_position_in_lane_m(pose, ahead, centre_left - half_width);
  return {inner_edge - left_wheel, right_wheel + inner_edge};
}

}  // namespace ccdlane::ldw
