// Starting point of a solve (docs/solver.md "Solving it well"): each pick's x from the ray-
// ground intersection at the initial pose, lines from a straight-line fit when not given.
#pragma once

#include <span>

#include "core/solver/lane_solver.hpp"

namespace ccdlane::solver {

// Ground points of the picks seen by a camera of `spec` at `pose` into `ground`
// (CameraModel::ground_point_from_pixel's). Returns the index of the first pick whose ray
// misses the road (or has no undistorted pixel), or -1.
int ground_points_of_picks(const CameraSpec& spec, const CameraPose& pose, std::span<const Pick> picks, Vec2* ground);

// Per line, the least-squares line y = y0 + m x through its picks' ground points (m = 0
// unless `fit_slope`, or when its points do not spread along x); c = 0. A line without
// picks gets y0 = 0.
void fit_initial_lines(std::span<const Pick> picks, const Vec2* ground, int num_lines, bool fit_slope, RoadLine* lines);

}  // namespace ccdlane::solver
