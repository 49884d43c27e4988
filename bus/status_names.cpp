// status_t's state codes are the values of base/device_states.hpp's enums, checked here
// at compile time, so the names come from one place.
#include "bus/status_names.hpp"

#include <ccdlane/status_t.hpp>

#include "base/device_states.hpp"

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

}  // namespace ccdlane
