// The bounds are checked with negated comparisons so that a NaN fails every one of them.
#include "bus/vehicle_state_check.hpp"

#include <cmath>

namespace ccdlane {

const char* to_string(VehicleRefusal r) {
  switch (r) {
    case VehicleRefusal::undecodable: return "undecodable";
    case VehicleRefusal::speed: return "speed";
    case VehicleRefusal::yaw_rate: return "yaw_rate";
    case VehicleRefusal::indicator: return "indicator";
  }
  return "?";
}

const char* to_string(GatewayState s) {
  switch (s) {
    case GatewayState::none: return "none";
    case GatewayState::ok: return "ok";
    case GatewayState::fault: return "fault";
  }
  return "?";
}

std::optional<VehicleRefusal> vehicle_state_refusal(const vehicle_state_t& m) {
  if (!(m.speed_mps >= 0.0 && m.speed_mps <= kMaxVehicleSpeedMps)) return VehicleRefusal::speed;
  if (m.has_yaw_rate && !(std::abs(m.yaw_rate_radps) <= kMaxVehicleYawRateRadps)) return VehicleRefusal::yaw_rate;
  if (m.turn_indicator < vehicle_state_t::TURN_INDICATOR_NONE ||
      m.turn_indicator > vehicle_state_t::TURN_INDICATOR_BOTH)
    return VehicleRefusal::indicator;
  return std::nullopt;
}

GatewayState gateway_state(bool heard, std::optional<std::int64_t> latest_good_ns, std::int64_t now_ns,
                           std::int64_t max_age_ns) {
  if (!heard) return GatewayState::none;
  return latest_good_ns && now_ns - *latest_good_ns <= max_age_ns ? GatewayState::ok : GatewayState::fault;
}

}  // namespace ccdlane
