// The camera's mount on the vehicle (yaw, pitch, roll, height) from a drive on a marked
// road: per-frame attitudes solved with H fixed at its nominal value, kept on straight
// stretches, averaged; H from the lane width measured against a known or prior width.
//
// Roll is not in a frame's solve: parallel lines of free offsets cannot tell a rolled
// camera from lines at other offsets. Lanes of one width can, so the frames are solved
// with roll fixed at a reference value, and the roll that makes three or more lines
// equally spaced is each frame's roll. A second pass with the reference at the first
// pass's roll removes what the wrong roll did to yaw and pitch (run_mount_passes).
#pragma once

#include <cmath>
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
  double psi_deg = 0.0, theta_deg = 0.0;
  double sigma_psi_deg = 0.0, sigma_theta_deg = 0.0;
  std::optional<double> phi_deg;  // from the lines' spacing: three or more lines only
  double c_per_mm = 0.0;          // the road's curvature (NaN when the solve could not tell)
  double lane_width_mm = 0.0;     // as measured with H at its nominal value
  double sigma_lane_width_mm = 0.0;
  double lateral_offset_mm = 0.0;      // from the own lane's centre, positive left
  std::optional<double> gyro_yaw_deg;  // the gyro's yaw, for the turn rate; any zero
};

// The estimator set up for calibration: yaw, pitch and the offsets free, roll fixed at
// `phi_deg`, one shared curvature per frame (to tell straight road from bends), and no
// priors on the attitude, H or the lane width, so that every frame's angles and width
// are the picture's alone. Gyro readings must not be passed to it either (they would
// pull pitch towards the gyro's).
LaneEstimatorOptions mount_estimator_options(LaneEstimatorOptions options, double phi_deg);

// The frame's MountFrame from the estimate (and the solve behind it, null if none),
// solved with roll fixed at `phi_deg` and H at `nominal_H_mm`.
MountFrame mount_frame(const LaneEstimate& estimate, const SolveResult* solution, const std::optional<Gx1Angles>& gyro,
                       double phi_deg, double nominal_H_mm);

// How far (degrees) the lines at lateral offsets y0_mm, seen from height H_mm, are turned
// about the vanishing point from lines equally spaced: the roll the solve was off by
// (subtract it from the roll the lines were solved with). None with fewer than three lines.
std::optional<double> equal_lanes_roll_deg(std::span<const double> y0_mm, double H_mm);

struct MountOptions {
  double nominal_H_mm = 1400.0;  // the H the frames were solved with
  // The true lane width: sigma 0 for a known width, else a prior (3.6 +- 0.2 m is the
  // usual spread of motorway lanes).
  Prior lane_width_mm{3600.0, 200.0};
  // Straight enough: |c| below 1/(2 R) of this radius (c of y = y0 + c x^2). The frames
  // are solved with the road's curvature, and the lane's direction at the camera is the
  // vehicle's on a bend as on a straight (freeway bends are 500 m or wider); sharper
  // bends are left out because the parabola is a poorer model of them.
  double min_radius_m = 500.0;
  // Turning (gyro yaw rate) or moving sideways faster than this: a lane change or a
  // swerve, not a drive along the lane. The lateral speed is taken over a window: frame
  // to frame, a few centimetres of offset noise at 25 frames/s is as fast as this.
  double max_yaw_rate_deg_s = 2.0;
  double max_lateral_speed_mm_s = 600.0;
  double lateral_speed_window_s = 1.0;
  double lane_change_guard_s = 2.0;  // frames this close to a lane change are dropped
  double max_gap_s = 0.5;            // a longer gap between kept frames ends a stretch
  // Stretches are cut into blocks this long; the blocks' spread gives the sigmas (the
  // heading wanders over seconds, so single frames are not independent samples).
  double block_s = 1.0;
  // Less straight driving than this determines nothing. A dashcam clip of a freeway is
  // often only a few seconds long, and misses lines in some of them.
  double min_straight_s = 4.0;
  // The frames are stills of one camera, each solved alone (a benchmark's pictures, from
  // unrelated clips): no time, no stretches; every still with lines on both sides, not
  // on a sharp bend, is one independent sample, and at least min_stills are needed.
  bool stills = false;
  int min_stills = 10;
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
  bool phi_determined = false;     // false: no stretch (or too few stills) showed three lines (phi_deg is then the reference)
  double measured_width_mm = 0.0;  // the lane width at the nominal H
  double sigma_measured_width_mm = 0.0;
  double straight_s = 0.0;  // time on the kept stretches
  int stretches = 0, blocks = 0;
  int frames = 0, frames_with_lane = 0, frames_kept = 0;
  int frames_curved = 0, frames_turning = 0, frames_lane_change = 0;
};

// `frames` in time order (or stills, options.stills), solved with roll fixed at
// `reference_phi_deg`.
MountCalibration calibrate_mount(std::span<const MountFrame> frames, const MountOptions& options = {},
                                 double reference_phi_deg = 0.0);

// Passes over a recording until roll settles (at most `max_passes`, from the nominal
// roll): `pass(phi_deg)` must run every frame through an estimator made with
// mount_estimator_options(..., phi_deg) and return their MountFrames.
template <typename Pass>
MountCalibration run_mount_passes(Pass&& pass, double nominal_phi_deg, const MountOptions& options,
                                  int max_passes = 2) {
  double phi = nominal_phi_deg;
  MountCalibration result;
  for (int i = 0; i < max_passes; ++i) {
    result = calibrate_mount(pass(phi), options, phi);
    if (result.status != MountStatus::ok || !result.phi_determined) break;
    const bool settled = std::abs(result.phi_deg - phi) < 0.1 * result.sigma_phi_deg;
    phi = result.phi_deg;
    if (settled) break;
  }
  return result;
}

const char* to_string(MountStatus status);

}  // namespace ccdlane::calibration
