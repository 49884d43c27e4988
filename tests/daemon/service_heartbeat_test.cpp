// READY once the first frame is through and WATCHDOG only while frames are processed:
// the heartbeat ticked like the daemon's main loop, on a real pipeline whose camera
// stalls, talking to a test-owned NOTIFY_SOCKET.
#include "daemon/service_heartbeat.hpp"

#include <unistd.h>

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "daemon/allocation_counter.hpp"
#include "daemon/pipeline.hpp"
#include "tests/daemon/notify_socket.hpp"
#include "tests/daemon/pipeline_doubles.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

class ServiceHeartbeatTest : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("NOTIFY_SOCKET", socket_.path().c_str(), 1);  // sd_notify reads it at every call
    setenv("WATCHDOG_USEC", "60000", 1);                 // pings at most every 20 ms
    unsetenv("WATCHDOG_PID");
  }
  void TearDown() override {
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
    allocation_counter::stop_counting();
  }
  test::TempDir dir_;
  test::NotifySocket socket_{dir_.file("notify")};
};

TEST_F(ServiceHeartbeatTest, NothingBeforeTheFirstFrameThenReadyOnce) {
  SystemdNotifier notifier;
  ServiceHeartbeat heartbeat(notifier);
  EXPECT_EQ(heartbeat.tick_period_ns(), 20'000'000);
  heartbeat.tick(1'000'000'000, false, 0);
  EXPECT_EQ(socket_.receive(50), std::nullopt);
  heartbeat.tick(1'100'000'000, true, 1);
  EXPECT_EQ(socket_.receive(1000), "READY=1");
  EXPECT_EQ(socket_.receive(1000), "WATCHDOG=1");
  heartbeat.tick(1'200'000'000, true, 5);
  EXPECT_EQ(socket_.receive(1000), "WATCHDOG=1");
  heartbeat.tick(1'300'000'000, true, 5);  // no progress since the last ping
  heartbeat.tick(1'400'000'000, true, 5);
  EXPECT_EQ(socket_.receive(50), std::nullopt);
  heartbeat.tick(1'500'000'000, true, 6);
  EXPECT_EQ(socket_.receive(1000), "WATCHDOG=1");
  EXPECT_TRUE(heartbeat.ready_sent());
}

TEST_F(ServiceHeartbeatTest, WatchdogStopsWhenTheCameraStalls) {
  SystemdNotifier notifier;
  ServiceHeartbeat heartbeat(notifier);
  test::RecordingSink sink(1000);
  test::StallingSource source(test::small_frames(0, 250), /*frames=*/100);  // 0.4 s of frames
  ASSERT_EQ(source.open(), "");
  TestPatternProcessor processor;
  RealtimeConfig rt_config;
  RealtimeSetup realtime(rt_config);
  PipelineOptions options;
  options.stall_timeout_ns = 100'000'000;
  options.capture_timeout_ms = 20;
  Pipeline pipeline(source, nullptr, processor, sink, realtime, options);
  pipeline.start();
  pipeline.run();

  // The main loop's job, with the test reading the socket as systemd would.
  std::vector<std::string> while_flowing;
  while (pipeline.totals().camera != CameraState::stalled) {
    const PipelineTotals t = pipeline.totals();
    heartbeat.tick(monotonic_ns(), t.ready, t.frames_processed);
    for (auto& m : socket_.drain()) while_flowing.push_back(m);
    std::this_thread::sleep_for(std::chrono::nanoseconds(heartbeat.tick_period_ns()));
  }
  ASSERT_GE(while_flowing.size(), 3u);
  EXPECT_EQ(while_flowing.front(), "READY=1");
  for (std::size_t i = 1; i < while_flowing.size(); ++i) EXPECT_EQ(while_flowing[i], "WATCHDOG=1");

  const std::uint64_t pings = notifier.watchdog_pings();
  for (int i = 0; i < 15; ++i) {  // 300 ms of stall, ticking as usual
    const PipelineTotals t = pipeline.totals();
    heartbeat.tick(monotonic_ns(), t.ready, t.frames_processed);
    std::this_thread::sleep_for(std::chrono::nanoseconds(heartbeat.tick_period_ns()));
  }
  // At most one ping for the frames finished just before the stall was noticed.
  EXPECT_LE(notifier.watchdog_pings(), pings + 1);
  socket_.drain();
  const std::uint64_t settled = notifier.watchdog_pings();
  for (int i = 0; i < 10; ++i) {
    const PipelineTotals t = pipeline.totals();
    heartbeat.tick(monotonic_ns(), t.ready, t.frames_processed);
    std::this_thread::sleep_for(std::chrono::nanoseconds(heartbeat.tick_period_ns()));
  }
  EXPECT_EQ(notifier.watchdog_pings(), settled) << "no ping while the camera is stalled";
  EXPECT_EQ(socket_.receive(50), std::nullopt);
  pipeline.stop();
}

}  // namespace
}  // namespace ccdlane
