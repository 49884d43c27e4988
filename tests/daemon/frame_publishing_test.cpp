// [lcm] publish_frames on memq://: the publisher sends each frame with its record and
// pixels; in the pipeline, the frames on the bus are the frames processed, under the
// numbers and times of their lane messages; failures are counted, never silent.
#include <vector>

#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>

#include "bus/frame_message.hpp"
#include "bus/lcm_publisher.hpp"
#include "bus/vehicle_state_listener.hpp"
#include "daemon/pipeline.hpp"
#include "tests/daemon/pipeline_doubles.hpp"
#include "tests/support/test_pattern_source.hpp"

namespace ccdlane {
namespace {

void on_frame(const lcm::ReceiveBuffer*, const std::string&, const frame_t* m, std::vector<frame_t>* got) {
  got->push_back(*m);
}

LcmConfig memq(const char* prefix = "CCDLANE_") { return LcmConfig{"memq://", prefix, true, ""}; }

TEST(FramePublishing, OffUntilEnabledThenEachFrameGoesOutWithItsRecordAndPixels) {
  LcmPublisher publisher(memq("CAR7_"));
  EXPECT_FALSE(publisher.publishes_frames()) << "off by default";
  std::vector<std::uint8_t> pixels(64 * 10);  // a padded stride, as the frame pool's
  const ImageView image{pixels.data(), 24, 10, 64, PixelFormat::mono8, 8};
  EXPECT_FALSE(publisher.publish_frame(image, FrameRecord{})) << "nothing to send with before enable_frames()";

  publisher.enable_frames(24, 10, PixelFormat::mono8);
  EXPECT_TRUE(publisher.publishes_frames());
  EXPECT_EQ(publisher.frames_channel(), "CAR7_FRAMES");
  std::vector<frame_t> got;
  publisher.bus().subscribeFunction("CAR7_FRAMES", &on_frame, &got);
  for (std::uint64_t k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i + k);
    const std::optional<Gx1Angles> gyro = k == 1 ? std::nullopt : std::optional<Gx1Angles>(Gx1Angles{0.5, -1.0, 33.0});
    ASSERT_TRUE(publisher.publish_frame(image, {k, static_cast<std::int64_t>(k) * 33'000'000, 1000, gyro}));
    while (got.size() < k + 1 && publisher.bus().handleTimeout(1000) > 0) {
    }
    ASSERT_EQ(got.size(), k + 1);
    const frame_t& m = got.back();
    EXPECT_EQ(m.sequence, static_cast<std::int64_t>(k));
    EXPECT_EQ(m.t_ns, static_cast<std::int64_t>(k) * 33'000'000);
    EXPECT_EQ(m.has_gyro, k != 1);
    if (k != 1) {
      EXPECT_EQ(m.gyro_yaw_deg, 33.0);
    }
    ImageView back;
    ASSERT_EQ(frame_image(m, back), "");
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 24; ++x) ASSERT_EQ(back.at(x, y), image.at(x, y));
  }
}

TEST(FramePublishing, AFrameOfAnotherSizeIsRefusedNotSent) {
  LcmPublisher publisher(memq());
  publisher.enable_frames(24, 10, PixelFormat::mono8);
  std::vector<frame_t> got;
  publisher.bus().subscribeFunction("CCDLANE_FRAMES", &on_frame, &got);
  std::vector<std::uint8_t> pixels(30 * 10);
  EXPECT_FALSE(publisher.publish_frame({pixels.data(), 30, 10, 30, PixelFormat::mono8, 8}, FrameRecord{}));
  while (publisher.bus().handleTimeout(0) > 0) {
  }
  EXPECT_TRUE(got.empty());
}

// Behind a queue that drops: the frames on the bus are exactly the frames processed, in
// processing order, under the numbers and times of their lane messages; so a log replays
// through the same estimator states the daemon went through.
TEST(FramePublishing, InThePipelineTheFramesSentAreTheFramesProcessedAfterDrops) {
  constexpr std::uint64_t kFrames = 400;
  TestPatternSource source(test::small_frames(kFrames, 0));  // as fast as it can render
  ASSERT_EQ(source.open(), "");
  LcmPublisher publisher(memq());
  publisher.enable_frames(source.width(), source.height(), source.format());
  std::vector<frame_t> got;
  got.reserve(kFrames);
  publisher.bus().subscribeFunction("CCDLANE_FRAMES", &on_frame, &got);
  std::vector<lane_estimate_t> lanes;
  publisher.bus().subscribeFunction(
      "CCDLANE_LANES",
      +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, std::vector<lane_estimate_t>* out) {
        out->push_back(*m);
      },
      &lanes);
  TestPatternProcessor processor(/*work_us=*/300);
  RealtimeConfig realtime_config;
  RealtimeSetup realtime{realtime_config};
  PipelineOptions options;
  options.queue_depth = 1;
  Pipeline pipeline(source, nullptr, processor, publisher, realtime, options);
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(test::eventually([&] { return pipeline.finished(); }, std::chrono::seconds(60)));
  pipeline.stop();
  while (publisher.bus().handleTimeout(0) > 0) {
  }

  const PipelineTotals t = pipeline.totals();
  EXPECT_GT(t.frames_dropped, 0u) << "the processor is far slower than the source";
  EXPECT_EQ(t.frame_publish_errors, 0u);
  ASSERT_EQ(lanes.size(), t.frames_processed);
  ASSERT_EQ(got.size(), lanes.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(got[i].sequence, lanes[i].frame) << "frame " << i;
    ASSERT_EQ(got[i].t_ns, lanes[i].t_ns) << "frame " << i;
    ImageView image;
    ASSERT_EQ(frame_image(got[i], image), "");
    EXPECT_TRUE(test_pattern_intact(image, static_cast<std::uint64_t>(lanes[i].frame)))
        << "the pixels of the frame processed, not a later one's";
  }
}

// The frames on the bus carry the vehicle inputs the frame was processed with (the bus's
// vehicle state), so that replaying a log of them gives the daemon's warnings.
TEST(FramePublishing, TheFramesCarryTheVehicleStateTheyWereProcessedWith) {
  constexpr std::uint64_t kFrames = 5;
  TestPatternSource source(test::small_frames(kFrames, 0));
  ASSERT_EQ(source.open(), "");
  LcmPublisher publisher(memq());
  publisher.enable_frames(source.width(), source.height(), source.format());
  std::vector<frame_t> got;
  publisher.bus().subscribeFunction("CCDLANE_FRAMES", &on_frame, &got);
  VehicleStateListener vehicle(publisher.bus().getUnderlyingLCM(), "CCDLANE_VEHICLE");
  vehicle_state_t state{};
  state.speed_mps = 25.0;
  state.has_yaw_rate = true;
  state.yaw_rate_radps = -0.02;
  state.turn_indicator = vehicle_state_t::TURN_INDICATOR_LEFT;
  publisher.bus().publish("CCDLANE_VEHICLE", &state);
  ASSERT_GT(publisher.bus().handleTimeout(1000), 0);
  ASSERT_EQ(vehicle.received(), 1u);

  TestPatternProcessor processor;
  RealtimeConfig realtime_config;
  RealtimeSetup realtime{realtime_config};
  Pipeline pipeline(source, nullptr, processor, publisher, realtime, PipelineOptions{});
  pipeline.set_vehicle_state(&vehicle, 3'600'000'000'000);  // never stale within the test
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(test::eventually([&] { return pipeline.finished(); }, std::chrono::seconds(60)));
  pipeline.stop();
  while (publisher.bus().handleTimeout(0) > 0) {
  }
  ASSERT_FALSE(got.empty());
  for (const frame_t& f : got) {
    const FrameRecord r = frame_record(f);
    EXPECT_EQ(r.speed_kmh, 25.0 * 3.6) << "frame " << f.sequence;
    EXPECT_EQ(r.yaw_rate_radps, -0.02) << "frame " << f.sequence;
    EXPECT_EQ(r.indicator, TurnIndicator::left) << "frame " << f.sequence;
  }
}

// A frame that cannot go out is counted where status_t reports it.
TEST(FramePublishing, FramesThatCannotBeSentAreCountedInThePipelineTotals) {
  TestPatternSource source(test::small_frames(20, 0));
  ASSERT_EQ(source.open(), "");
  LcmPublisher publisher(memq());
  publisher.enable_frames(source.width() + 2, source.height(), source.format());  // not the frames' size
  TestPatternProcessor processor;
  RealtimeConfig realtime_config;
  RealtimeSetup realtime{realtime_config};
  Pipeline pipeline(source, nullptr, processor, publisher, realtime, PipelineOptions{});
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(test::eventually([&] { return pipeline.finished(); }, std::chrono::seconds(60)));
  pipeline.stop();
  const PipelineTotals t = pipeline.totals();
  EXPECT_GT(t.frames_processed, 0u);
  EXPECT_EQ(t.frame_publish_errors, t.frames_processed) << "every processed frame failed, and was counted";
  EXPECT_EQ(t.publish_errors, 0u) << "the lane messages still went out";
}

}  // namespace
}  // namespace ccdlane
