// ccdlaned end to end on a real multicast bus in a private network namespace: rendered
// frames in, one lane message per frame out, the same estimates as `ccdlane replay`; and
// the gyro emulator hanging up mid-run without the lane messages stopping.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include "daemon/lane_message.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"
#include "tools/ccdlane/lane_estimate_json.hpp"

namespace ccdlane {
namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::ordered_json;

const std::string kDaemon = CCDLANE_DAEMON;
const std::string kTool = CCDLANE_TOOL;
const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";

struct Received {
  std::vector<lane_estimate_t> lanes;
  std::vector<status_t> statuses;
};

void subscribe(lcm::LCM& bus, Received& got) {
  bus.subscribeFunction(
      "CCDLANE_LANES",
      +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, Received* g) { g->lanes.push_back(*m); },
      &got);
  bus.subscribeFunction(
      "CCDLANE_STATUS",
      +[](const lcm::ReceiveBuffer*, const std::string&, const status_t* m, Received* g) { g->statuses.push_back(*m); },
      &got);
}

// Renders `frames` frames of the default synthetic drive (with its gyro columns).
std::string render(const test::TempDir& dir, int frames, const std::vector<std::string>& extra = {}) {
  const std::string config = dir.write("synth.toml", "");
  const std::string out = dir.file("frames");
  std::vector<std::string> argv = {kTool, "synth", config, "--out", out, "--frames", std::to_string(frames)};
  argv.insert(argv.end(), extra.begin(), extra.end());
  const auto r = test::run_process(argv);
  EXPECT_EQ(r.exit_status, 0) << r.err;
  return out;
}

// Same value: numbers within a tolerance far below anything the estimator resolves (the
// two runs do the same arithmetic on the same pixels and gyro readings), the rest equal.
void expect_same(const ordered_json& daemon, const ordered_json& replay, const std::string& where) {
  if (daemon.is_number() && replay.is_number()) {  // signed or not is the JSON library's business
    const double a = daemon.get<double>(), b = replay.get<double>();
    EXPECT_NEAR(a, b, 1e-9 * std::max(1.0, std::fabs(b))) << where;
    return;
  }
  ASSERT_EQ(daemon.type(), replay.type()) << where << ": " << daemon << " vs " << replay;
  if (daemon.is_object()) {
    for (const auto& [key, value] : replay.items()) {
      if (key == "latency_us") continue;  // the clocks of two different runs; t_ns is the recorded one
      ASSERT_TRUE(daemon.contains(key)) << where << "." << key;
      expect_same(daemon[key], value, where + "." + key);
    }
    EXPECT_EQ(daemon.size(), replay.size()) << where;
  } else if (daemon.is_array()) {
    ASSERT_EQ(daemon.size(), replay.size()) << where;
    for (std::size_t i = 0; i < daemon.size(); ++i) expect_same(daemon[i], replay[i], where + "[" + std::to_string(i) + "]");
  } else {
    EXPECT_EQ(daemon, replay) << where;
  }
}

// The daemon on a frame directory (no gyro device: the frames.csv columns give the
// priors, as in replay), paced fast and not looping: it stops by itself at the end.
TEST(CcdlanedEndToEnd, FramesSourceGivesOneMessagePerFrameMatchingReplay) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(kUrl);
  ASSERT_TRUE(bus.good());
  Received got;
  subscribe(bus, got);

  test::TempDir dir;
  constexpr int kFrames = 40;
  const std::string frames = render(dir, kFrames);
  const std::string config =
      dir.write("daemon.toml", "[source]\nkind = \"frames\"\npath = \"" + frames + "\"\nrate_hz = 100\n");
  test::ChildProcess daemon({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  std::optional<int> exit_status;
  const auto end = Clock::now() + std::chrono::seconds(30);
  while (!exit_status && Clock::now() < end) {
    bus.handleTimeout(50);
    exit_status = daemon.wait_exit(0);
  }
  while (bus.handleTimeout(200) > 0) {
  }
  ASSERT_TRUE(exit_status.has_value()) << "the end of a finite source stops the daemon";
  EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << test::read_file(dir.file("stderr"));

  const auto replay = test::run_process({kTool, "replay", config, frames});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  std::vector<ordered_json> expected;
  std::istringstream lines(replay.out);
  for (std::string line; std::getline(lines, line);) expected.push_back(ordered_json::parse(line));
  ASSERT_EQ(expected.size(), static_cast<std::size_t>(kFrames));

  ASSERT_EQ(got.lanes.size(), static_cast<std::size_t>(kFrames)) << test::read_file(dir.file("stderr"));
  int ok = 0;
  for (int i = 0; i < kFrames; ++i) {
    const lane_estimate_t& m = got.lanes[static_cast<std::size_t>(i)];
    EXPECT_EQ(m.frame, i) << "in order, none missing";
    expect_same(cli::lane_estimate_json(from_message(m)), expected[static_cast<std::size_t>(i)], "frame " + std::to_string(i));
    ok += m.ok;
  }
  EXPECT_GE(ok, kFrames - 2) << "the synthetic road is an easy one";
  ASSERT_FALSE(got.statuses.empty());
  EXPECT_EQ(got.statuses.back().allocations_since_ready, 0);
  EXPECT_EQ(got.statuses.back().frames_dropped_total, 0);
}

// The 3DM-GX1 emulator (another process, on a pty behind a link) hangs up every 1.3 s
// for 300 ms: frames keep being processed and published throughout, the status counts
// the hang-ups, and the gyro comes back.
TEST(CcdlanedEndToEnd, GyroHangUpsDoNotStopTheLaneMessages) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(kUrl);
  ASSERT_TRUE(bus.good());
  Received got;
  subscribe(bus, got);

  test::TempDir dir;
  const std::string frames = render(dir, 20, {"--no-gyro"});  // the gyro device is the only source of priors
  const std::string link = dir.file("gx1");
  test::ChildProcess emulator({kTool, "gx1-emulate", "--link", link, "--attitude", "0,-3,0", "--hangup-every", "1.3",
                               "--hangup-ms", "300"},
                              test::ChildOptions{{}, dir.file("emulator.out"), dir.file("emulator.err"), {}});
  struct stat st {};
  for (int i = 0; i < 100 && lstat(link.c_str(), &st) != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(lstat(link.c_str(), &st), 0) << test::read_file(dir.file("emulator.err"));

  const std::string config = dir.write("daemon.toml", "[source]\nkind = \"frames\"\npath = \"" + frames +
                                                          "\"\nrate_hz = 50\nloop = true\n[gyro]\ndevice = \"" + link +
                                                          "\"\n");
  test::ChildProcess daemon({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  const auto end = Clock::now() + std::chrono::milliseconds(4500);
  while (Clock::now() < end) bus.handleTimeout(100);
  daemon.signal(SIGTERM);
  const auto exit_status = daemon.wait_exit(2000);
  while (bus.handleTimeout(100) > 0) {
  }
  const std::string log = test::read_file(dir.file("stderr"));
  ASSERT_TRUE(exit_status.has_value()) << log;
  EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << log;

  // About 4 s at 50 frames a second with no gap: no stretch of 200 ms without a message.
  ASSERT_GE(got.lanes.size(), 150u) << log;
  for (std::size_t i = 1; i < got.lanes.size(); ++i) {
    EXPECT_EQ(got.lanes[i].frame, got.lanes[i - 1].frame + 1) << "none dropped";
    EXPECT_LT(got.lanes[i].publish_utime - got.lanes[i - 1].publish_utime, 200'000) << "frame " << got.lanes[i].frame;
  }
  ASSERT_FALSE(got.statuses.empty());
  const status_t& last = got.statuses.back();
  EXPECT_GE(last.gyro_errors_total, 2) << "hang-ups are counted: " << log;
  EXPECT_EQ(last.allocations_since_ready, 0);
  // Some frames had the gyro's priors and some (while it was away) had none; status ticks
  // and hang-ups both come about once a second, so the state seen at ticks is no proof.
  EXPECT_GT(last.gyro_samples_total, 0);
  EXPECT_GT(last.no_attitude_total, 0) << log;
  EXPECT_LT(last.no_attitude_total, last.frames_processed_total) << log;
}

}  // namespace
}  // namespace ccdlane
