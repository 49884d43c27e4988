// status_t's state codes are the values of base/device_states.hpp's enums, checked here
// at compile time, so the names come from one place.
#include "bus/status_names.hpp"

#include <ccdlane/status_t.hpp>

#include "base/device_states.hpp"
#include "bus/vehicle_state_check.hpp"

namespace ccdlane {

static_assert(status_t::CAMERA_STARTING == static_cast<int>(CameraState::starting));
static_assert(status_t::CAMERA_STREAMING == static_cast<int>(CameraState::streaming));
static_assert(status_t::CAMERA_STALLED == static_cast<int>(CameraState::stalled));
static_assert(status_t::CAMERA_RECOVERING == static_cast<int>(CameraState::recovering));
static_assert(status_t::CAMERA_ENDED == static_cast<int>(CameraState::ended));
static_assert(status_t::GYRO_NONE == static_cast<int>(GyroState::none));
static_assert(status_t::GYRO_STARTING == static_cast<int>(GyroState::starting));
static_assert(status_t::GYRO_OK == static_cast<int>(GyroState::ok));
static_assert(status_t::GYRO_STALE == static_cast<int>(GyroState::stale));
static_assert(status_t::GYRO_LOST == static_cast<int>(GyroState::lost));
static_assert(status_t::VEHICLE_NONE == static_cast<int>(GatewayState::none));
static_assert(status_t::VEHICLE_OK == static_cast<int>(GatewayState::ok));
static_assert(status_t::VEHICLE_FAULT == static_cast<int>(GatewayState::fault));
static_assert(status_t::VEHICLE_REFUSED_UNDECODABLE == static_cast<int>(VehicleRefusal::undecodable));
static_assert(status_t::VEHICLE_REFUSED_SPEED == static_cast<int>(VehicleRefusal::speed));
static_assert(status_t::VEHICLE_REFUSED_YAW_RATE == static_cast<int>(VehicleRefusal::yaw_rate));
static_assert(status_t::VEHICLE_REFUSED_INDICATOR == static_cast<int>(VehicleRefusal::indicator));
static_assert(sizeof(status_t::vehicle_refused_by_cause) / sizeof(std::int64_t) == kVehicleRefusalKinds);

const char* camera_state_name(int code) {
  return code >= 0 && code <= status_t::CAMERA_ENDED ? to_string(static_cast<CameraState>(code)) : "unknown";
}

const char* gyro_state_name(int code) {
  return code >= 0 && code <= status_t::GYRO_LOST ? to_string(static_cast<GyroState>(code)) : "unknown";
}

const char* calibration_state_name(int code) {
  switch (code) {
    case status_t::CALIBRATION_OFF: return "off";
    case status_t::CALIBRATION_UNCALIBRATED: return "uncalibrated";
    case status_t::CALIBRATION_CALIBRATING: return "calibrating";
    case status_t::CALIBRATION_CALIBRATED: return "calibrated";
    case status_t::CALIBRATION_OUT_OF_RANGE: return "out_of_range";
    default: return "unknown";
  }
}

const char* vehicle_state_name(int code) {
  return code >= 0 && code <= status_t::VEHICLE_FAULT ? to_string(static_cast<GatewayState>(code)) : "unknown";
}

const char* vehicle_refusal_name(int code) {
  return code >= 0 && code < kVehicleRefusalKinds ? to_string(static_cast<VehicleRefusal>(code)) : "unknown";
}

}  // namespace ccdlane
