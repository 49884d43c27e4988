// The one state per device kind that status messages, logs and `ccdlane monitor` show:
// the camera's and the gyro's. Their values are status_t's CAMERA_* and GYRO_* constants
// (checked in bus/status_names.cpp). The drivers' bring-up steps (drivers/device_state.hpp)
// are finer and internal: a driver's "recovering" shows here as recovering, its
// "streaming" as streaming until frames stop coming (stalled).
#pragma once

#include <cstdint>

namespace ccdlane {

enum class CameraState : std::uint8_t { starting, streaming, stalled, recovering, ended };
enum class GyroState : std::uint8_t { none, starting, ok, stale, lost };

constexpr const char* to_string(CameraState s) {
  switch (s) {
    case CameraState::starting: return "starting";
    case CameraState::streaming: return "streaming";
    case CameraState::stalled: return "stalled";
    case CameraState::recovering: return "recovering";
    case CameraState::ended: return "ended";
  }
  return "unknown";
}

constexpr const char* to_string(GyroState s) {
  switch (s) {
    case GyroState::none: return "none";
    case GyroState::starting: return "starting";
    case GyroState::ok: return "ok";
    case GyroState::stale: return "stale";
    case GyroState::lost: return "lost";
  }
  return "unknown";
}

}  // namespace ccdlane
