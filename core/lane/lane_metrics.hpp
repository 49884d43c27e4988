// What the lane lines mean for the vehicle (docs/interfaces.md "Per-frame result"): its own
// lane's width, its offset from the lane's centre, its heading, and lane departure.
#pragma once

#include <cstddef>
#include <span>

#include "core/geometry/road_line.hpp"  // own_lane_lines
#include "core/lane/lane_estimate.hpp"

namespace ccdlane {

// The narrowest traffic lanes are 2.5 m (work-zone lanes, the narrowest national
// standards; motorways have 3.5-3.75 m); a pair of lines closer than that, beside a car
// about 1.8 m wide, is not a lane to drive in (noise made such pairs at 2.0-2.4 m).
constexpr double kMinLaneWidthMm = 2500.0;
constexpr double kMaxLaneWidthMm = 5500.0;  // wider: a line in between was missed

struct LaneMetrics {
  bool has_lane = false;      // a line on each side of the vehicle
  int left = -1, right = -1;  // indices of the own lane's lines, -1 = none on that side
  double lane_width_mm = 0.0;
  double lateral_offset_mm = 0.0;
  double heading_deg = 0.0;
  double curvature_per_m = 0.0;  // the own lane's, at the vehicle; positive bending left
  Departure departure = Departure::none;
};

// `lines` ordered left to right (largest y0 first). The own lane is bounded by the
// nearest line with y0 > 0 (left) and the nearest with y0 <= 0 (right); it is a lane
// only when they are kMinLaneWidthMm..kMaxLaneWidthMm apart.
//   lane_width = y0_left - y0_right, lateral_offset = -(y0_left + y0_right) / 2;
//   heading = psi - mount_psi - atan(m), m the mean slope of the own lane's lines
//     (0 when m is not estimated): positive when the vehicle points left of the lane;
//   curvature = 2 c / (1 + m^2)^(3/2), per metre, c and m the means over the own lane's
//     lines (whichever exist): the lines are parallel, so either one's is the lane's;
//   departure: "left" when the own lane's left line is nearer than departure_mm to the
//     vehicle's centre (the fixed frame's origin), "right" likewise, the nearer side
//     when both are; "none" otherwise or without a lane.
LaneMetrics lane_metrics(std::span<const EstimatedLine> lines, double psi_deg, double mount_psi_deg,
                         double departure_mm);

}  // namespace ccdlane
