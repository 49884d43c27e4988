// Defaults and small helpers of the configuration schema.
#include "app/config.hpp"

namespace ccdlane {
CameraPose Config::nominal_pose() const {
  CameraPose pose;
  pose.attitude = {deg_to_rad(attitude.psi_deg), deg_to_rad(attitude.theta_deg), deg_to_rad(attitude.phi_deg)};
  pose.H_mm = H_mm;
  pose.f_mm = f_mm;
  return pose;
}

LaneEstimatorOptions Config::estimator_options() const {
  LaneEstimatorOptions o;
  o.camera = camera;
  o.nominal_pose = nominal_pose();
  o.solver = solver;
  o.priors = prior;
  o.gyro_sigma_deg = gyro.sigma_deg;
  o.detection = detection;
  o.ldw = ldw;
  o.ldw.vehicle = vehicle;
  // With a gyro its roll is the solve's prior: the lane filter tracks roll only without one.
  o.ldw.filter.track_roll = gyro.device.empty();
  return o;
}

calibration::OnlineMountOptions Config::online_mount_options() const {
  calibration::OnlineMountOptions o;
  o.configured_psi_deg = attitude.psi_deg;
  o.configured_theta_deg = attitude.theta_deg;
  o.min_speed_kmh = calibration.min_speed_kmh;
  o.max_curvature_per_m = 1.0 / calibration.min_radius_m;
  o.max_correction_deg = calibration.max_correction_deg;
  o.max_change_deg_per_min = calibration.max_change_deg_per_min;
  o.frames_needed = calibration.frames_needed;
  return o;
}

Config default_config() {
  Config c;
  c.camera = CameraSpec{};
  c.camera.k_px2 = -8.3042e-7;
  c.camera.yM_mm = -27.25;
  c.camera.zM_mm = 2.53;
  return c;
}

}  // namespace ccdlane
