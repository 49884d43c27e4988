// The one set of rules for a frame's inputs: the frame's own values first, then what is
// live, and the devices' health, as the daemon, replay and calibrate all apply them.
#include "app/frame_inputs.hpp"

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

const std::uint8_t kPixel = 0;
const ImageView kImage{&kPixel, 1, 1, 1, PixelFormat::mono8};

TEST(FrameInputs, ARecordedFrameKeepsItsOwnGyroAndVehicle) {
  FrameMeta meta;
  meta.sequence = 7;
  meta.t_ns = 100;
  meta.recorded_t_ns = 40;
  meta.gyro = Gx1Angles{1.0, 2.0, 3.0};
  meta.speed_kmh = 36.0;
  meta.indicator = TurnIndicator::left;
  LiveReadings live;
  live.gyro = Gx1Angles{9.0, 9.0, 9.0};
  live.yaw_rate_radps = 0.5;
  live.vehicle = VehicleInputs{};
  live.vehicle->speed_mps = 30.0;
  const FrameInputs in = frame_inputs(&kImage, 3, meta, live, true);
  EXPECT_EQ(in.frame, 3u);
  EXPECT_EQ(in.source_frame, 7u);
  EXPECT_EQ(in.t_ns, 40);
  ASSERT_TRUE(in.gyro);
  EXPECT_EQ(in.gyro->roll_deg, 1.0);
  EXPECT_EQ(in.attitude_source, AttitudeSource::recorded);
  EXPECT_DOUBLE_EQ(*in.vehicle.speed_mps, 10.0);
  EXPECT_EQ(in.vehicle.indicator, TurnIndicator::left);
  EXPECT_FALSE(in.vehicle.yaw_rate_radps) << "a recording was not turned by this gyro";
  EXPECT_TRUE(in.vehicle.camera_ok);
  EXPECT_TRUE(in.vehicle.gyro_ok);
}

TEST(FrameInputs, ALiveFrameTakesTheLiveGyroAndTheBus) {
  FrameMeta meta;
  meta.t_ns = 100;
  LiveReadings live;
  live.gyro = Gx1Angles{1.0, 2.0, 3.0};
  live.yaw_rate_radps = 0.5;
  live.vehicle = VehicleInputs{};
  live.vehicle->speed_mps = 30.0;
  const FrameInputs in = frame_inputs(&kImage, 0, meta, live, true);
  EXPECT_EQ(in.attitude_source, AttitudeSource::live);
  EXPECT_DOUBLE_EQ(*in.vehicle.speed_mps, 30.0);
  EXPECT_DOUBLE_EQ(*in.vehicle.yaw_rate_radps, 0.5);
  EXPECT_EQ(in.t_ns, 100);
}

TEST(FrameInputs, AConfiguredGyroWithoutAReadingIsAtFaultAndAnUnreadableFrameIsTheCameras) {
  const FrameMeta meta;
  const FrameInputs missing = frame_inputs(&kImage, 0, meta, LiveReadings{}, true);
  EXPECT_EQ(missing.attitude_source, AttitudeSource::none);
  EXPECT_FALSE(missing.vehicle.gyro_ok);
  EXPECT_TRUE(frame_inputs(&kImage, 0, meta, LiveReadings{}, false).vehicle.gyro_ok) << "no gyro configured";

  LiveReadings stale;
  stale.gyro_delivering = false;
  const FrameInputs bad = frame_inputs(nullptr, 0, meta, stale, true);
  EXPECT_FALSE(bad.image);
  EXPECT_FALSE(bad.vehicle.camera_ok);
  EXPECT_FALSE(bad.vehicle.gyro_ok) << "an unreadable frame: the live gyro's state says";
}

}  // namespace
}  // namespace ccdlane
