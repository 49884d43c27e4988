// [lcm] publish_frames on a real multicast bus (udpm:// in a private network namespace):
// publishing a frame uses no operator new, and what lcm-logger records of the frames the
// lane estimator processed replays (`ccdlane replay CONFIG FILE.lcmlog`) to exactly the
// estimates it returned, gyro priors included.
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "app/config_loader.hpp"
#include "base/clock.hpp"
#include "base/image_buffer.hpp"
#include "bus/lcm_publisher.hpp"
#include "core/lane/lane_estimator.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/synth_drive.hpp"
#include "daemon/allocation_counter.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"
#include "tools/ccdlane/json_output.hpp"
#include "tools/ccdlane/lane_estimate_json.hpp"

namespace ccdlane {
namespace {

const std::string kUrl = test::kBusUrl;
const std::string kConfig = CCDLANE_SOURCE_DIR "/tools/demo/reference-camera.toml";

// Renders the synthetic drive of a configuration frame by frame.
class SynthFrames {
 public:
  explicit SynthFrames(const Config& config)
      : drive_(config.synth, config.nominal_pose()),
        renderer_(config.camera, config.synth),
        buffer_(config.camera.Nu, config.camera.Nv, renderer_.format(), config.synth.bits) {}
  const SynthFrame& render(std::uint64_t k) {
    frame_ = drive_.frame(k);
    renderer_.render(frame_, buffer_.view());
    return frame_;
  }
  const MutableImageView& image() const { return buffer_.view(); }

 private:
  SynthDrive drive_;
  RoadRenderer renderer_;
  ImageBuffer buffer_;
  SynthFrame frame_;
};

std::string without_latency(const std::string& line) {
  return std::regex_replace(line, std::regex(R"(,"latency_us":[0-9]+)"), "");
}

class FramePublisherBus : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  }
};

TEST_F(FramePublisherBus, PublishingAFrameUsesNoOperatorNew) {
  LcmPublisher publisher(LcmConfig{kUrl, "CCDLANE_", true, ""});
  publisher.enable_frames(800, 600, PixelFormat::mono8);
  std::vector<std::uint8_t> pixels(800 * 600, 7);
  const ImageView image{pixels.data(), 800, 600, 800, PixelFormat::mono8, 8};
  ASSERT_TRUE(publisher.publish_frame(image, FrameRecord{}));  // LCM sets up its send path on first use
  const std::uint64_t before = allocation_counter::in_this_thread();
  int sent = 0;
  for (std::uint64_t k = 1; k <= 20; ++k) sent += publisher.publish_frame(image, {k, 0, 0, Gx1Angles{1.0, 2.0, 3.0}});
  EXPECT_EQ(allocation_counter::in_this_thread() - before, 0u);
  EXPECT_EQ(sent, 20);
}

TEST_F(FramePublisherBus, WhatLcmLoggerRecordsReplaysToTheSameEstimates) {
  const Config config = load_config_file(kConfig);
  test::TempDir dir;
  const std::string log = dir.file("drive.lcmlog");
  // Frames are ~0.5 MB: the default receive buffer drops them (platform-notes.md).
  test::ChildProcess logger({"/usr/bin/lcm-logger", "--lcm-url=" + kUrl + "&recv_buf_size=8388608", log},
                            {{}, dir.file("logger.out"), dir.file("logger.err"), {}});
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));  // subscribed by then
  ASSERT_FALSE(logger.wait_exit(0).has_value()) << test::read_file(dir.file("logger.err"));

  LcmPublisher publisher(LcmConfig{kUrl, "CCDLANE_", true, ""});
  publisher.enable_frames(config.camera.Nu, config.camera.Nv, PixelFormat::mono8);
  LaneEstimator estimator(config.estimator_options());
  SynthFrames synth(config);
  constexpr std::uint64_t kFrames = 15;
  std::vector<std::string> published;
  for (std::uint64_t k = 0; k < kFrames; ++k) {
    const SynthFrame& f = synth.render(k);
    // As the daemon's pipeline does: estimate, then the frame under the estimate's keys.
    const LaneEstimate e = estimator.estimate(synth.image(), k, f.t_ns, f.gyro);
    ASSERT_TRUE(publisher.publish_frame(synth.image(), {k, f.t_ns, realtime_us(), f.gyro}));
    std::ostringstream line;
    cli::print_json_line(line, cli::lane_estimate_json(e));
    published.push_back(without_latency(line.str()));
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  logger.signal(SIGINT);
  const auto status = logger.wait_exit(5000);
  ASSERT_TRUE(status.has_value()) << "lcm-logger did not stop";

  const auto r = test::run_process({CCDLANE_TOOL, "replay", kConfig, log});
  ASSERT_EQ(r.exit_status, 0) << r.err << test::read_file(dir.file("logger.err"));
  std::vector<std::string> replayed;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) replayed.push_back(without_latency(line + "\n"));
  ASSERT_EQ(replayed.size(), kFrames) << "every frame recorded: " << r.err;
  EXPECT_EQ(replayed, published);
  EXPECT_NE(published[kFrames - 1].find("\"ok\":true"), std::string::npos) << "real estimates are compared";
}

}  // namespace
}  // namespace ccdlane
