// State names: one per status_t constant, "unknown" outside them, and the C++ enums
// print through the same table.
#include "bus/status_names.hpp"

#include <ccdlane/status_t.hpp>
#include <gtest/gtest.h>

#include "app/attitude_provider.hpp"
#include "daemon/pipeline_totals.hpp"

namespace ccdlane {
namespace {

TEST(StatusNames, CameraStates) {
  EXPECT_STREQ(camera_state_name(status_t::CAMERA_STARTING), "starting");
  EXPECT_STREQ(camera_state_name(status_t::CAMERA_STREAMING), "streaming");
  EXPECT_STREQ(camera_state_name(status_t::CAMERA_STALLED), "stalled");
  EXPECT_STREQ(camera_state_name(status_t::CAMERA_RECOVERING), "recovering");
  EXPECT_STREQ(camera_state_name(status_t::CAMERA_ENDED), "ended");
  EXPECT_STREQ(camera_state_name(-1), "unknown");
  EXPECT_STREQ(camera_state_name(5), "unknown");
  EXPECT_STREQ(to_string(CameraState::stalled), "stalled");
}

TEST(StatusNames, GyroStates) {
  EXPECT_STREQ(gyro_state_name(status_t::GYRO_NONE), "none");
  EXPECT_STREQ(gyro_state_name(status_t::GYRO_STARTING), "starting");
  EXPECT_STREQ(gyro_state_name(status_t::GYRO_OK), "ok");
  EXPECT_STREQ(gyro_state_name(status_t::GYRO_STALE), "stale");
  EXPECT_STREQ(gyro_state_name(status_t::GYRO_LOST), "lost");
  EXPECT_STREQ(gyro_state_name(100), "unknown");
  EXPECT_STREQ(to_string(GyroState::lost), "lost");
}

TEST(StatusNames, VehicleStatesAndRefusals) {
  EXPECT_STREQ(vehicle_state_name(status_t::VEHICLE_NONE), "none");
  EXPECT_STREQ(vehicle_state_name(status_t::VEHICLE_OK), "ok");
  EXPECT_STREQ(vehicle_state_name(status_t::VEHICLE_FAULT), "fault");
  EXPECT_STREQ(vehicle_state_name(3), "unknown");
  EXPECT_STREQ(vehicle_refusal_name(status_t::VEHICLE_REFUSED_UNDECODABLE), "undecodable");
  EXPECT_STREQ(vehicle_refusal_name(status_t::VEHICLE_REFUSED_SPEED), "speed");
  EXPECT_STREQ(vehicle_refusal_name(status_t::VEHICLE_REFUSED_YAW_RATE), "yaw_rate");
  EXPECT_STREQ(vehicle_refusal_name(status_t::VEHICLE_REFUSED_INDICATOR), "indicator");
  EXPECT_STREQ(vehicle_refusal_name(-1), "unknown");
}

TEST(StatusNames, CalibrationStates) {
  EXPECT_STREQ(calibration_state_name(status_t::CALIBRATION_OFF), "off");
  EXPECT_STREQ(calibration_state_name(status_t::CALIBRATION_UNCALIBRATED), "uncalibrated");
  EXPECT_STREQ(calibration_state_name(status_t::CALIBRATION_CALIBRATING), "calibrating");
  EXPECT_STREQ(calibration_state_name(status_t::CALIBRATION_CALIBRATED), "calibrated");
  EXPECT_STREQ(calibration_state_name(status_t::CALIBRATION_OUT_OF_RANGE), "out_of_range");
  EXPECT_STREQ(calibration_state_name(5), "unknown");
}

}  // namespace
}  // namespace ccdlane
