// The track stage of the lane estimator: a fitted solve's lines given the ids the tracker
// follows them by, ordered left to right with their support and confidence, and what
// they make of the own lane (lane_metrics.hpp).
#pragma once

#include <array>

#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_fit.hpp"
#include "core/lane/lane_metrics.hpp"
#include "core/lane/lane_tracker.hpp"

namespace ccdlane {

struct TrackedLines {
  int num_lines = 0;
  std::array<EstimatedLine, kMaxLaneLines> lines{};  // left to right (largest y0 first)
  std::array<int, kMaxLaneLines> solve_line{};       // per line of `lines`: its index in the solve
  LaneMetrics metrics;                               // of `lines`
  OwnLane own;  // the own lane's lines as indices into the solve's lines, and its measures
};

// Updates `tracker` with the solve's lines (those `fit` continued from its priors keep
// their ids). `mount_psi_deg`: the yaw the heading is measured from.
TrackedLines track_lines(LaneTracker& tracker, const SolveResult& r, const LaneFit& fit, double mount_psi_deg,
                         double departure_mm);

}  // namespace ccdlane
