// What the lane estimator is built from; the configuration maps onto it
// (Config::estimator_options), so core never depends on the configuration.
#pragma once

#include "core/detection/detection_config.hpp"
#include "core/geometry/camera_model.hpp"
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
};

}  // namespace ccdlane
