// `ccdlane spy` for real: CTest runs this program under `xvfb-run -a`, so lcm-spy gets a
// display. On a private multicast bus it starts, finds every ccdlane type, stays up while
// lane and status messages arrive, and is java itself (exec'd, so signals reach it).
// lcm-spy's own decoding path (type lookup by fingerprint over the class path) is replayed
// on its class path by SpyDecodeCheck.java against messages encoded here.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "bus/channels.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kTool = CCDLANE_TOOL;
const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";

lane_estimate_t lane_message(std::int64_t frame) {
  lane_estimate_t m{};
  m.frame = frame;
  m.t_ns = frame * 33'333'333;
  m.ok = true;
  m.psi_deg = 1.05;
  m.num_lines = 2;
  m.lines[0].y0_mm = 1750.0;
  m.lines[1].y0_mm = -1850.0;
  m.lane_width_mm = 3600.0;
  m.lateral_offset_mm = -49.5;
  m.departure = lane_estimate_t::DEPARTURE_NONE;
  return m;
}

status_t status_message() {
  status_t s{};
  s.ready = true;
  s.frames_in = 30;
  s.camera = "synth 800x600 mono8 30 fps";
  s.camera_state = status_t::CAMERA_STREAMING;
  return s;
}

template <typename Message>
std::string encode_to(const test::TempDir& dir, const std::string& name, const Message& m) {
  std::vector<char> bytes(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return dir.write(name, std::string(bytes.begin(), bytes.end()));
}

// The CLASSPATH `ccdlane spy --print-command` reports.
std::string spy_classpath() {
  const auto r = test::run_process({kTool, "spy", "--print-command"});
  EXPECT_EQ(r.exit_status, 0) << r.err;
  const std::string key = "CLASSPATH=";
  if (r.out.rfind(key, 0) != 0) return "";
  return r.out.substr(key.size(), r.out.find(' ') - key.size());
}

TEST(SpyCommand, PrintCommandNamesTheJarsAndTheBus) {
  const auto r = test::run_process({kTool, "spy", "--print-command", "--lcm", "udpm://239.255.76.67:7700?ttl=0"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.out.find("/usr/share/java/lcm.jar:/usr/share/java/jchart2d.jar:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ccdlane_lcmtypes.jar"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("'-Djava.net.preferIPv4Stack=true' 'lcm.spy.Spy' "
                       "'--lcm-url=udpm://239.255.76.67:7700?ttl=0'"),
            std::string::npos)
      << r.out;
}

TEST(SpyCommand, MissingJavaOrDisplayIsOneClearLine) {
  auto r = test::run_process({"/usr/bin/env", "PATH=/nonexistent", kTool, "spy"});
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_EQ(r.err, "ccdlane: spy: no java on PATH; install a Java runtime with AWT: apt-get install default-jre\n");
  r = test::run_process({"/usr/bin/env", "-u", "DISPLAY", "-u", "WAYLAND_DISPLAY", kTool, "spy"});
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.err.find("there is no display (DISPLAY is not set)"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(SpyCommand, ItsClassPathDecodesCcdlaneMessagesAsLcmSpyDoes) {
  test::TempDir dir;
  const std::string lane = encode_to(dir, "lane.bin", lane_message(12));
  const std::string status = encode_to(dir, "status.bin", status_message());
  const std::string classpath = spy_classpath();
  ASSERT_FALSE(classpath.empty());
  const auto r =
      test::run_process({"/usr/bin/env", "CLASSPATH=" + classpath + ":" + CCDLANE_SPY_CHECK_CLASSES, CCDLANE_JAVA,
                         "SpyDecodeCheck", lane, "lateral_offset_mm", status, "camera", lane, "frame"});
  ASSERT_EQ(r.exit_status, 0) << r.out << r.err;
  EXPECT_EQ(r.out, "Found " + std::to_string(CCDLANE_LCM_TYPE_COUNT) +
                       " LCM types\n"
                       "ccdlane.lane_estimate_t lateral_offset_mm=-49.5\n"
                       "ccdlane.status_t camera=synth 800x600 mono8 30 fps\n"
                       "ccdlane.lane_estimate_t frame=12\n");
}

TEST(SpyCommand, StartsLcmSpyWithTheCcdlaneTypesOnALiveBus) {
  ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run -a (CTest does)";
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir dir;
  const std::string out = dir.file("spy.out");
  test::ChildProcess spy({kTool, "spy", "--lcm", kUrl}, {{}, out, dir.file("spy.err"), {}});

  // "Found N plugins" is printed once the window is built.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (test::read_file(out).find(" plugins") == std::string::npos) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline)
        << "lcm-spy did not come up:\n"
        << test::read_file(out) << test::read_file(dir.file("spy.err"));
    ASSERT_FALSE(spy.wait_exit(100).has_value()) << "lcm-spy exited:\n"
                                                 << test::read_file(out) << test::read_file(dir.file("spy.err"));
  }
  // exec'd: the process we started is java now, not a parent waiting for it.
  const std::string exe = std::filesystem::read_symlink("/proc/" + std::to_string(spy.pid()) + "/exe");
  EXPECT_EQ(std::filesystem::path(exe).filename(), "java") << exe;

  lcm::LCM bus(kUrl);
  ASSERT_TRUE(bus.good());
  const std::string lanes = channel_name("CCDLANE_", Channel::lanes);
  const std::string statuses = channel_name("CCDLANE_", Channel::status);
  const status_t status = status_message();
  for (int i = 0; i < 60; ++i) {
    const lane_estimate_t lane = lane_message(i);
    ASSERT_EQ(bus.publish(lanes, &lane), 0);
    if (i % 10 == 0) {
      ASSERT_EQ(bus.publish(statuses, &status), 0);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  EXPECT_FALSE(spy.wait_exit(500).has_value()) << "lcm-spy stopped while messages arrived";

  spy.signal(SIGTERM);
  const auto exit = spy.wait_exit(10000);
  ASSERT_TRUE(exit.has_value()) << "SIGTERM did not end lcm-spy";
  const std::string text = test::read_file(out) + test::read_file(dir.file("spy.err"));
  EXPECT_NE(text.find("Found " + std::to_string(CCDLANE_LCM_TYPE_COUNT) + " LCM types"), std::string::npos) << text;
  EXPECT_EQ(text.find("Spy.messageReceived ex"), std::string::npos) << text;
  EXPECT_EQ(text.find("Exception"), std::string::npos) << text;
}

}  // namespace
}  // namespace ccdlane
