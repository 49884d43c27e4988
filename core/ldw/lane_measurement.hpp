// One frame's solve as the lane filter's measurement: the own lane's two lines, heading,
// curvature, pitch and roll in SI units, with their covariance carried over from the
// solver's (so correlations, e.g. both lines moving with the roll, are kept).
#pragma once

#include "core/ldw/lane_filter.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane::ldw {

// `left_line`, `right_line`: indices into result.lines of the own lane's lines (the
// nearest with y0 > 0 and y0 <= 0, as lane_metrics picks them). `mount_psi_rad`: the
// configured mounting yaw (heading = psi - mount - atan(mean m), as in lane_metrics).
// `roll_is_measured`: the filter tracks roll (no gyro); otherwise roll is left absent.
//   curvature = c_left + c_right (the mean of the two lines' 2c), per metre;
// Components the solve did not determine (fixed parameters, NaN covariance) are absent.
LaneMeasurement measurement_from_solve(const SolveResult& result, int left_line, int right_line, double mount_psi_rad,
                                       bool roll_is_measured);

}  // namespace ccdlane::ldw
