// sd_notify against a test-owned NOTIFY_SOCKET: the messages, their wording, and the
// watchdog's rate limit.
#include "daemon/sd_notifier.hpp"

#include <unistd.h>

#include <cstdlib>
#include <string>

#include <gtest/gtest.h>

#include "tests/daemon/notify_socket.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

class SdNotifierTest : public ::testing::Test {
 protected:
  void TearDown() override {
    unsetenv("NOTIFY_SOCKET");
    unsetenv("WATCHDOG_USEC");
    unsetenv("WATCHDOG_PID");
  }
  test::TempDir dir_;
};

TEST_F(SdNotifierTest, WithoutNotifySocketEverythingIsANoOp) {
  unsetenv("NOTIFY_SOCKET");
  SystemdNotifier n;
  EXPECT_FALSE(n.enabled());
  EXPECT_EQ(n.watchdog_interval_us(), 0);
  n.ready();
  n.status("fine");
  n.watchdog_kick(1);
  n.stopping();
  EXPECT_EQ(n.watchdog_pings(), 0u);
}

TEST_F(SdNotifierTest, SendsReadyStatusWatchdogStopping) {
  test::NotifySocket socket(dir_.file("notify"));
  setenv("NOTIFY_SOCKET", socket.path().c_str(), 1);
  setenv("WATCHDOG_USEC", "300000", 1);
  setenv("WATCHDOG_PID", std::to_string(getpid()).c_str(), 1);
  SystemdNotifier n;
  EXPECT_TRUE(n.enabled());
  EXPECT_EQ(n.watchdog_interval_us(), 300000);

  n.ready();
  EXPECT_EQ(socket.receive(1000), "READY=1");
  n.status("streaming 30.0 fps");
  EXPECT_EQ(socket.receive(1000), "STATUS=streaming 30.0 fps");
  n.status(std::string(400, 's').c_str());
  EXPECT_EQ(socket.receive(1000), "STATUS=" + std::string(200, 's'));

  // At most one ping per third of the period (100 ms here), whatever the frame rate.
  const std::int64_t t0 = 5'000'000'000;
  n.watchdog_kick(t0);
  n.watchdog_kick(t0 + 50'000'000);
  n.watchdog_kick(t0 + 99'000'000);
  n.watchdog_kick(t0 + 100'000'000);
  n.watchdog_kick(t0 + 150'000'000);
  EXPECT_EQ(n.watchdog_pings(), 2u);
  EXPECT_EQ(socket.receive(1000), "WATCHDOG=1");
  EXPECT_EQ(socket.receive(1000), "WATCHDOG=1");
  EXPECT_EQ(socket.receive(50), std::nullopt);

  n.stopping();
  EXPECT_EQ(socket.receive(1000), "STOPPING=1");
}

TEST_F(SdNotifierTest, AWatchdogMeantForAnotherProcessIsIgnored) {
  test::NotifySocket socket(dir_.file("notify"));
  setenv("NOTIFY_SOCKET", socket.path().c_str(), 1);
  setenv("WATCHDOG_USEC", "300000", 1);
  setenv("WATCHDOG_PID", std::to_string(getpid() + 1).c_str(), 1);
  SystemdNotifier n;
  EXPECT_EQ(n.watchdog_interval_us(), 0);
  n.watchdog_kick(1);
  EXPECT_EQ(socket.receive(50), std::nullopt);
}

}  // namespace
}  // namespace ccdlane
