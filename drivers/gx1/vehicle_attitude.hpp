// The attitudes a road vehicle's gyro can report: a reading beyond them is damage or a
// broken sensor, and taken as a prior it makes every frame fail (too_few_marks) while
// the gyro looks healthy.
#pragma once

#include "base/gx1_angles.hpp"

namespace ccdlane::gx1 {

// Beyond 45 degrees of roll a vehicle is rolling over; pitch adds the camera's downward
// tilt (the sensor is mounted with it, docs/gx1.md section 13) to the steepest road
// grade, with margin. Yaw is a heading: any value in the sensor's -180..180.
inline constexpr double kMaxVehicleRollDeg = 45.0;
inline constexpr double kMaxVehiclePitchDeg = 60.0;

// Which angle lies beyond its bound ("roll", "pitch", "yaw"; a NaN does too), or nullptr.
const char* implausible_vehicle_angle(const Gx1Angles& a);

}  // namespace ccdlane::gx1
