// [lcm] publish_frames on memq://: the decorator publishes each processed frame under the
// source's sequence number and frame time (as the pipeline keys its lane message, whatever
// the inner estimate says) with the gyro reading used, returns the inner processor's
// estimate untouched, and is only put in place when the key asks for it.
#include "daemon/frame_publisher.hpp"

#include <vector>

#include <gtest/gtest.h>

#include "daemon/pipeline.hpp"
#include "tests/support/test_pattern_source.hpp"
#include "bus/frame_message.hpp"
#include "tests/daemon/pipeline_doubles.hpp"

namespace ccdlane {
namespace {

// The inner processor: an estimate numbered and timed its own way, so the test sees
// that the published frame carries the source's numbers instead.
class NumberingProcessor : public FrameProcessor {
 public:
  LaneEstimate process(const ImageView&, const FrameMeta& meta, std::optional<Gx1Angles>) override {
    LaneEstimate e;
    e.frame = meta.sequence + 1000;
    e.t_ns = static_cast<std::int64_t>(meta.sequence) * 40'000'000;
    e.ok = true;
    e.lateral_offset_mm = -12.5;
    ++calls;
    return e;
  }
  int calls = 0;
};

void on_frame(const lcm::ReceiveBuffer*, const std::string&, const frame_t* m, std::vector<frame_t>* got) {
  got->push_back(*m);
}

TEST(FramePublisher, PublishesEachProcessedFrameUnderTheSourcesNumberAndFrameTime) {
  lcm::LCM bus("memq://");
  ASSERT_TRUE(bus.good());
  std::vector<frame_t> got;
  bus.subscribeFunction("CCDLANE_FRAMES", &on_frame, &got);
  auto inner = std::make_unique<NumberingProcessor>();
  NumberingProcessor& counting = *inner;
  FramePublishingProcessor publisher(std::move(inner), bus, "CCDLANE_FRAMES", 24, 10, PixelFormat::mono8);

  std::vector<std::uint8_t> pixels(64 * 10);  // a padded stride, as the frame pool's
  for (std::uint64_t k = 0; k < 3; ++k) {
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i + k);
    const ImageView image{pixels.data(), 24, 10, 64, PixelFormat::mono8, 8};
    FrameMeta meta;
    meta.sequence = k;
    meta.t_ns = 5 + static_cast<std::int64_t>(k);  // the capture clock
    if (k != 2) meta.recorded_t_ns = static_cast<std::int64_t>(k) * 33'000'000;  // a recorded frame's own time
    const std::optional<Gx1Angles> gyro = k == 1 ? std::nullopt : std::optional<Gx1Angles>(Gx1Angles{0.5, -1.0, 33.0});
    const LaneEstimate e = publisher.process(image, meta, gyro);
    EXPECT_EQ(e.frame, k + 1000);
    EXPECT_EQ(e.lateral_offset_mm, -12.5) << "the inner estimate, untouched";
    while (got.size() < k + 1 && bus.handleTimeout(1000) > 0) {}
    ASSERT_EQ(got.size(), k + 1);
    const frame_t& m = got.back();
    EXPECT_EQ(m.sequence, static_cast<std::int64_t>(k));
    EXPECT_EQ(m.t_ns, k != 2 ? static_cast<std::int64_t>(k) * 33'000'000 : 7) << "as recorded, else the capture time";
    EXPECT_EQ(m.has_gyro, k != 1);
    if (k != 1) {
      EXPECT_EQ(m.gyro_yaw_deg, 33.0);
    }
    ImageView back;
    ASSERT_EQ(frame_image(m, back), "");
    for (int y = 0; y < 10; ++y)
      for (int x = 0; x < 24; ++x) ASSERT_EQ(back.at(x, y), image.at(x, y));
  }
  EXPECT_EQ(counting.calls, 3);
  EXPECT_EQ(publisher.published(), 3u);
  EXPECT_EQ(publisher.failed(), 0u);
}

// In the daemon's pipeline, behind a queue that drops: the frames on the bus are exactly
// the frames processed, in processing order, under the numbers and times of their lane
// messages; so a log replays through the same estimator states the daemon went through.
TEST(FramePublisher, InThePipelineTheFramesSentAreTheFramesProcessedAfterDrops) {
  constexpr std::uint64_t kFrames = 400;
  lcm::LCM bus("memq://");
  ASSERT_TRUE(bus.good());
  std::vector<frame_t> got;
  got.reserve(kFrames);
  bus.subscribeFunction("CCDLANE_FRAMES", &on_frame, &got);
  test::RecordingSink sink(kFrames);
  TestPatternSource source(test::small_frames(kFrames, 0));  // as fast as it can render
  ASSERT_EQ(source.open(), "");
  FramePublishingProcessor processor(std::make_unique<TestPatternProcessor>(/*work_us=*/300), bus, "CCDLANE_FRAMES",
                                     source.width(), source.height(), source.format());
  RealtimeConfig realtime_config;
  RealtimeSetup realtime{realtime_config};
  PipelineOptions options;
  options.queue_depth = 1;
  Pipeline pipeline(source, nullptr, processor, sink, realtime, options);
  pipeline.start();
  pipeline.run();
  ASSERT_TRUE(test::eventually([&] { return pipeline.finished(); }, std::chrono::seconds(60)));
  pipeline.stop();
  while (bus.handleTimeout(0) > 0) {
  }

  const PipelineTotals t = pipeline.totals();
  const auto lanes = sink.records();
  EXPECT_GT(t.frames_dropped, 0u) << "the processor is far slower than the source";
  ASSERT_EQ(got.size(), lanes.size());
  ASSERT_EQ(processor.published(), lanes.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_EQ(static_cast<std::uint64_t>(got[i].sequence), lanes[i].frame) << "frame " << i;
    ImageView image;
    ASSERT_EQ(frame_image(got[i], image), "");
    EXPECT_TRUE(test_pattern_intact(image, lanes[i].frame)) << "the pixels of the frame processed, not a later one's";
  }
}

TEST(FramePublisher, AFrameOfAnotherSizeIsCountedNotSent) {
  lcm::LCM bus("memq://");
  FramePublishingProcessor publisher(std::make_unique<NumberingProcessor>(), bus, "F", 24, 10, PixelFormat::mono8);
  std::vector<std::uint8_t> pixels(30 * 10);
  const ImageView wrong{pixels.data(), 30, 10, 30, PixelFormat::mono8, 8};
  EXPECT_EQ(publisher.process(wrong, FrameMeta{}, std::nullopt).frame, 1000u);
  EXPECT_EQ(publisher.published(), 0u);
  EXPECT_EQ(publisher.failed(), 1u);
}

TEST(FramePublisher, TheDaemonHookWrapsOnlyWhenPublishFramesIsSet) {
  Config config = default_config();
  config.lcm.url = "memq://";
  config.lcm.prefix = "CAR7_";
  LcmPublisher lanes(config.lcm);
  TestPatternSource source({.width = 16, .height = 8, .rate_hz = 0.0, .frames = 0});
  ASSERT_EQ(source.open(), "");

  auto plain = std::make_unique<NumberingProcessor>();
  FrameProcessor* const raw = plain.get();
  EXPECT_EQ(with_frame_publishing(std::move(plain), config, lanes, source).get(), raw) << "off by default";

  config.lcm.publish_frames = true;
  std::unique_ptr<FrameProcessor> wrapped =
      with_frame_publishing(std::make_unique<NumberingProcessor>(), config, lanes, source);
  auto* publishing = dynamic_cast<FramePublishingProcessor*>(wrapped.get());
  ASSERT_NE(publishing, nullptr);
  EXPECT_EQ(publishing->channel(), "CAR7_FRAMES");
  std::vector<frame_t> got;
  lanes.bus().subscribeFunction("CAR7_FRAMES", &on_frame, &got);
  std::vector<std::uint8_t> pixels(16 * 8);
  const MutableImageView image{pixels.data(), 16, 8, 16, PixelFormat::mono8, 8};
  FrameMeta meta;
  ASSERT_EQ(source.capture(image, meta, 100), CaptureStatus::frame);
  wrapped->process(image, meta, std::nullopt);
  while (got.empty() && lanes.bus().handleTimeout(1000) > 0) {}
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].width, 16);
  EXPECT_EQ(got[0].height, 8);
}

}  // namespace
}  // namespace ccdlane
