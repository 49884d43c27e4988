// docs/gx1.md section 13: conjugating by diag(1, -1, -1) flips rotations about y and z.
#include "core/geometry/gx1_attitude.hpp"

namespace ccdlane {

Attitude camera_attitude_from_gx1(const Gx1Angles& sensor) {
  return {deg_to_rad(-sensor.yaw_deg), deg_to_rad(-sensor.pitch_deg), deg_to_rad(sensor.roll_deg)};
}

}  // namespace ccdlane
