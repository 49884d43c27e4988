// Time to line crossing (TLC) of a wheel: when, at its present lateral velocity and
// acceleration relative to the lane, it reaches the line's inner edge.
#pragma once

#include <optional>

namespace ccdlane::ldw {

// Solves dlc = approach * t + approach_accel * t^2 / 2 for the first t >= 0.
//   dlc_m: distance to line crossing (positive inside);
//   approach_mps: lateral velocity toward the line (positive: approaching);
//   approach_accel_mps2: lateral acceleration toward the line relative to the lane, from
//     the difference of the vehicle's and the lane's curvature (v * (yaw_rate - v * kappa)).
// Empty when the wheel is not approaching the line now (approach <= 0) or when it slows
// down before reaching it. Zero when already on or beyond the edge and approaching.
std::optional<double> time_to_line_crossing(double dlc_m, double approach_mps, double approach_accel_mps2);

}  // namespace ccdlane::ldw
