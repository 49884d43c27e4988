// What the lane estimator is built from; the configuration maps onto it
// (Config::estimator_options), so core never depends on the configuration.
#pragma once

#include <optional>

#include "core/detection/detection_config.hpp"
#include "core/geometry/camera_model.hpp"
#include "core/lane/online_mount_refiner.hpp"
#include "core/ldw/ldw_monitor.hpp"
#include "core/solver/solver_options.hpp"

namespace ccdlane {

struct LaneEstimatorOptions {
  CameraSpec camera;
  CameraPose nominal_pose;  // the mount: the guess before any frame, and the yaw heading is measured from
  SolverOptions solver;
  SolverPriors priors;          // a prior here overrides the gyro's for the same angle
  double gyro_sigma_deg = 0.5;  // the gyro's roll and pitch become priors with this sigma
  DetectionConfig detection;
  // The lane departure warning, with the vehicle. filter.track_roll: without a gyro
  // (the solve's roll then is the only measure of it).
  ldw::LdwConfig ldw;
  // Online mount refinement (mount_refinement.hpp): off unless the caller turns it on.
  // ccdlaned does with [calibration] online; Config::estimator_options() leaves it off
  // (replay and calibrate mount do not learn the mount while they run).
  std::optional<calibration::OnlineMountOptions> online_mount;
  // Where the refinement starts: a mount learned before (ccdlaned's state file), already
  // checked against online_mount's bounds. Empty: uncalibrated, no correction.
  std::optional<calibration::LearnedMount> learned_mount;
};

}  // namespace ccdlane
