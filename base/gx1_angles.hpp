// One attitude sample as the 3DM-GX1 reports it (sensor axes, degrees): what the gyro
// driver produces, frame files record and the estimator turns into camera priors.
#pragma once

namespace ccdlane {

// Sensor angles as the 3DM-GX1 reports them, degrees (docs/gx1.md section 13).
struct Gx1Angles {
  double roll_deg = 0.0;
  double pitch_deg = 0.0;
  double yaw_deg = 0.0;
};

}  // namespace ccdlane
