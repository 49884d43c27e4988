// Physical bounds on the vehicle states a CAN gateway sends (vehicle_state_t): which
// messages are refused and why, and when the vehicle's inputs are at fault (LDW
// "vehicle_fault") rather than merely absent.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include <ccdlane/vehicle_state_t.hpp>

namespace ccdlane {

// Why a message was refused; the values index status_t.vehicle_refused_by_cause.
enum class VehicleRefusal : std::uint8_t {
  undecodable,  // another type (hash), truncated or damaged
  speed,        // not a number, negative or above kMaxVehicleSpeedMps
  yaw_rate,     // not a number or beyond kMaxVehicleYawRateRadps either way
  indicator,    // not one of TURN_INDICATOR_*
};
inline constexpr int kVehicleRefusalKinds = 4;
const char* to_string(VehicleRefusal r);  // "undecodable", "speed", "yaw_rate", "indicator"

// No road vehicle goes faster (252 km/h) or turns faster (a 5 m radius at 10 m/s); a
// value beyond is a broken gateway, and taken would warn falsely or silence warnings.
inline constexpr double kMaxVehicleSpeedMps = 70.0;
inline constexpr double kMaxVehicleYawRateRadps = 2.0;

// Why a decoded message cannot be a vehicle's state; nullopt when it can.
std::optional<VehicleRefusal> vehicle_state_refusal(const vehicle_state_t& m);

// The gateway as status and LDW see it: none heard yet ([vehicle] speed_kmh is then
// assumed: a vehicle without a gateway), delivering, or at fault: it was heard (a state
// taken or refused) and no good state is fresh, because it sends only refused states or
// fell silent. Its values are status_t's VEHICLE_*.
enum class GatewayState : std::uint8_t { none, ok, fault };
const char* to_string(GatewayState s);  // "none", "ok", "fault"

// What status reports of the gateway.
struct GatewayCounters {
  GatewayState state = GatewayState::none;
  std::uint64_t taken = 0;
  std::array<std::uint64_t, kVehicleRefusalKinds> refused{};  // indexed by VehicleRefusal
};

// `heard`: any message arrived; `latest_good_ns`: when the newest taken one did
// (CLOCK_MONOTONIC), none before the first.
GatewayState gateway_state(bool heard, std::optional<std::int64_t> latest_good_ns, std::int64_t now_ns,
                           std::int64_t max_age_ns);

}  // namespace ccdlane
