// Names of status_t's camera and gyro states, for the daemon's logs and for subscribers
// that print status messages.
#pragma once

namespace ccdlane {

// status_t::CAMERA_* -> "starting", "streaming", "stalled", "recovering", "ended".
const char* camera_state_name(int code);
// status_t::GYRO_* -> "none", "starting", "ok", "stale", "lost".
const char* gyro_state_name(int code);
// status_t::CALIBRATION_* -> "off", "uncalibrated", "calibrating", "calibrated", "out_of_range".
const char* calibration_state_name(int code);
// status_t::VEHICLE_* -> "none", "ok", "fault".
const char* vehicle_state_name(int code);
// status_t::VEHICLE_REFUSED_* -> "undecodable", "speed", "yaw_rate", "indicator".
const char* vehicle_refusal_name(int code);

}  // namespace ccdlane
