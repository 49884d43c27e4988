// The camera's mount on the vehicle (yaw, pitch, roll, height) from a drive on a marked
// road: per-frame attitudes solved with H fixed at its nominal value, kept on straight
// stretches, averaged; H from the lane width measured against a known or prior width.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "base/gx1_angles.hpp"
#include "core/lane/lane_estimate.hpp"
#include "core/lane/lane_estimator.hpp"
#include "core/solver/lane_solver.hpp"
#include "core/solver/solver_options.hpp"

namespace ccdlane::calibration {

// What one frame says about the mount.
struct MountFrame {
  std::int64_t t_ns = 0;
  bool lane = false;  // solved, with lines on both sides of the vehicle
  double psi_deg = 0.0, theta_deg = 0.0, phi_deg = 0.0;
  double sigma_psi_deg = 0.0, sigma_theta_deg = 0.0, sigma_phi_deg = 0.0;
  double c_per_mm = 0.0;           // the road's curvature (NaN when the solve could not tell)
  double lane_width_mm = 0.0;      // as measured with H at its nominal value
  double lateral_offset_mm = 0.0;  // from the own lane's centre, positive left
  std::optional<double> gyro_yaw_deg;  // the gyro's yaw, for the turn rate; any zero
};

// The estimator set up for calibration: one shared curvature per frame (to tell straight
// road from bends) and no priors on the attitude, H or the lane width, so that every
// frame's angles and width are the picture's alone. Gyro readings must not be passed to
// it either (they would pull roll and pitch towards the gyro's).
LaneEstimatorOptions mount_estimator_options(LaneEstimatorOptions options);

// The frame's MountFrame from the estimate (and the solve behind it, null if none).
MountFrame mount_frame(const LaneEstimate& estimate, const SolveResult* solution,
                       const std::optional<Gx1Angles>& gyro);

struct MountOptions {
  double nominal_H_mm = 1400.0;  // the H the frames were solved with
  // The true lane width: sigma 0 for a known width, else a prior (3.6 +- 0.2 m is the
  // usual spread of motorway lanes).
  Prior lane_width_mm{3600.0, 200.0};
  // Straight: |c| below 1/(2 R) of this radius (c of y = y0 + c x^2).
  double min_radius_m = 1500.0;
  // Turning (gyro yaw rate) or moving sideways faster than this: a lane change or a
  // swerve, not a drive along the lane.
  double max_yaw_rate_deg_s = 2.0;
  double max_lateral_speed_mm_s = 600.0;
  double lane_change_guard_s = 2.0;  // frames this close to a lane change are dropped
  double max_gap_s = 0.5;            // a longer gap between kept frames ends a stretch
  // Stretches are cut into blocks this long; the blocks' spread gives the sigmas (the
  // heading wanders over seconds, so single frames are not independent samples).
  double block_s = 2.0;
  double min_straight_s = 6.0;       // less straight driving than this determines nothing
};

enum class MountStatus {
  ok,
  no_lines,     // no frame with lane lines on both sides
  only_curves,  // lines seen, but (nearly) all of them on bends
  too_short,    // too little straight driving with lines on both sides
};

struct MountCalibration {
  MountStatus status = MountStatus::too_short;
  std::string message;  // why, for anything but ok
  double psi_deg = 0.0, theta_deg = 0.0, phi_deg = 0.0, H_mm = 0.0;
  double sigma_psi_deg = 0.0, sigma_theta_deg = 0.0, sigma_phi_deg = 0.0, sigma_H_mm = 0.0;
  double measured_width_mm = 0.0;  // the lane width at the nominal H
  double sigma_measured_width_mm = 0.0;
  double straight_s = 0.0;  // time on the kept stretches
  int stretches = 0, blocks = 0;
  int frames = 0, frames_with_lane = 0, frames_kept = 0;
  int frames_curved = 0, frames_turning = 0, frames_lane_change = 0;
};

// `frames` in time order.
MountCalibration calibrate_mount(std::span<const MountFrame> frames, const MountOptions& options = {});

const char* to_string(MountStatus status);

}  // namespace ccdlane::calibration
