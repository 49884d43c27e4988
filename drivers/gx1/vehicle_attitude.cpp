// Negated comparisons, so that a NaN angle fails its bound.
#include "drivers/gx1/vehicle_attitude.hpp"

#include <cmath>

namespace ccdlane::gx1 {

const char* implausible_vehicle_angle(const Gx1Angles& a) {
  if (!(std::abs(a.roll_deg) <= kMaxVehicleRollDeg)) return "roll";
  if (!(std::abs(a.pitch_deg) <= kMaxVehiclePitchDeg)) return "pitch";
  if (!(std::abs(a.yaw_deg) <= 180.0)) return "yaw";
  return nullptr;
}

}  // namespace ccdlane::gx1
