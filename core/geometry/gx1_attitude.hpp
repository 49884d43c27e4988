// The 3DM-GX1's Euler angles (NED-style, sensor axes) as the camera attitude of
// docs/geometry.md (docs/gx1.md section 13).
#pragma once

#include "base/gx1_angles.hpp"
#include "core/geometry/attitude.hpp"

namespace ccdlane {

// With the sensor's printed axes aligned to the camera (x along the optical axis, y to
// the right of the picture, z down): phi = roll, theta = -pitch, psi = -yaw. Another
// mounting is a fixed rotation applied to the sensor angles before this (not yet
// configurable). Yaw is magnetic heading: never use the result's psi as an absolute prior.
Attitude camera_attitude_from_gx1(const Gx1Angles& sensor);

}  // namespace ccdlane
