// `ccdlane monitor` watching a real ccdlaned on a private multicast bus: JSON objects
// with exactly the replay fields, one per lane message, in order; a live line a second;
// exit status 1 and one line when nothing arrives.
#include <signal.h>
#include <sys/wait.h>

#include <chrono>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "bus/lane_message.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Json = nlohmann::ordered_json;
const std::string kTool = CCDLANE_TOOL;
const std::string kDaemon = CCDLANE_DAEMON;
const std::string kUrl = "udpm://239.255.76.67:7667?ttl=0";

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

class MonitorCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
    const std::string config =
        dir_.write("ccdlane.toml", "[synth]\nframes = 10\n[source]\nrate_hz = 50\n[lcm]\nurl = \"" + kUrl + "\"\n");
    daemon_ = std::make_unique<test::ChildProcess>(std::vector<std::string>{kDaemon, "--config", config},
                                                   test::ChildOptions{{}, "", dir_.file("daemon.log"), {}});
  }
  void TearDown() override {
    if (!daemon_) return;
    daemon_->signal(SIGTERM);
    const auto status = daemon_->wait_exit(2000);
    ASSERT_TRUE(status.has_value());
    EXPECT_EQ(WEXITSTATUS(*status), 0);
  }
  test::TempDir dir_;
  std::unique_ptr<test::ChildProcess> daemon_;
};

TEST_F(MonitorCommand, JsonIsOneObjectPerLaneMessageWithTheReplayFields) {
  const auto r = test::run_process({kTool, "monitor", "--lcm", kUrl, "--count", "20", "--json", "--seconds", "20"});
  ASSERT_EQ(r.exit_status, 0) << r.err << test::read_file(dir_.file("daemon.log"));
  // Status messages come as {"status": {...}} objects between the lane messages.
  std::vector<std::string> lines;
  int statuses = 0;
  for (const std::string& line : lines_of(r.out)) {
    const Json j = Json::parse(line);
    if (!j.contains("status")) {
      lines.push_back(line);
      continue;
    }
    ++statuses;
    EXPECT_EQ(j.size(), 1u) << line;
    EXPECT_EQ(j["status"]["calibration"]["state"], "off") << "no [calibration] online: " << line;
  }
  ASSERT_EQ(lines.size(), 20u);
  EXPECT_LE(statuses, 20) << "one a second, 20 lanes at 50 fps";
  const std::vector<std::string> fields = {"frame",
                                           "t_ns",
                                           "ok",
                                           "state",
                                           "psi_deg",
                                           "theta_deg",
                                           "phi_deg",
                                           "H_mm",
                                           "lines",
                                           "lane_width_mm",
                                           "lateral_offset_mm",
                                           "heading_deg",
                                           "curvature_per_m",
                                           "radius_of_curvature_m",
                                           "departure",
                                           "rms_px",
                                           "iterations",
                                           "latency_us",
                                           "ldw"};
  std::uint64_t previous = 0;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const Json j = Json::parse(lines[i]);
    std::vector<std::string> keys;
    for (auto it = j.begin(); it != j.end(); ++it) keys.push_back(it.key());
    EXPECT_EQ(keys, fields) << lines[i];
    if (i > 0) {
      EXPECT_GT(j["frame"].get<std::uint64_t>(), previous) << "in order";
    }
    previous = j["frame"].get<std::uint64_t>();
    EXPECT_TRUE(j["ok"].get<bool>());
    EXPECT_EQ(j["departure"], "none");
    ASSERT_EQ(j["lines"].size(), 4u);  // the default synthetic road: 3 lanes
    std::vector<std::string> line_keys;
    for (auto it = j["lines"][0].begin(); it != j["lines"][0].end(); ++it) line_keys.push_back(it.key());
    EXPECT_EQ(line_keys,
              (std::vector<std::string>{"id", "y0_mm", "m", "c_per_mm", "marks", "confidence", "near_mm", "far_mm"}));
    // Left to right, 3.6 m apart as rendered.
    EXPECT_NEAR(j["lines"][0]["y0_mm"].get<double>() - j["lines"][1]["y0_mm"].get<double>(), 3600.0, 100.0);
  }
}

// --json into a full device: exit 1 with the reason, not a silent exit 0.
TEST_F(MonitorCommand, JsonOnAFullDeviceExitsOne) {
  const auto r = test::run_process({"/bin/sh", "-c", "exec \"$@\" >/dev/full", "sh", kTool, "monitor", "--lcm", kUrl,
                                    "--count", "5", "--json", "--seconds", "20"});
  EXPECT_EQ(r.exit_status, 1) << r.err;
  EXPECT_NE(r.err.find("standard output: cannot write: No space left on device"), std::string::npos) << r.err;
}

TEST_F(MonitorCommand, WithoutJsonALiveLineASecond) {
  const auto r = test::run_process({kTool, "monitor", "--lcm", kUrl, "--seconds", "3.5"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const auto lines = lines_of(r.out);
  ASSERT_GE(lines.size(), 2u) << r.out;
  bool saw_status = false;
  for (const std::string& line : lines) {
    if (line.rfind("no lane messages", 0) == 0) continue;  // before the daemon's first frame
    EXPECT_EQ(line.rfind("frame ", 0), 0u) << line;
    EXPECT_NE(line.find(" ok | psi "), std::string::npos) << line;
    EXPECT_NE(line.find("departure none, tracking | "), std::string::npos) << "a steady road is tracked: " << line;
    EXPECT_NE(line.find(", radius "), std::string::npos) << line;
    EXPECT_NE(line.find(" | LDW "), std::string::npos) << line;
    saw_status = saw_status || line.find("| camera streaming, gyro none") != std::string::npos;
  }
  EXPECT_TRUE(saw_status) << r.out;
}

// What a daemon publishes for 2.3 s: an ok lane message every 20 ms and `status` with
// every tenth, for a monitor started to read 2.5 s.
void publish_for_monitor(lcm::LCM& bus, const status_t& status, LaneEstimate e = {}) {
  e.ok = true;
  lane_estimate_t lane;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(2300);
  for (std::uint64_t frame = 0; std::chrono::steady_clock::now() < end; ++frame) {
    e.frame = frame;
    to_message(e, 0, 0, lane);
    bus.publish("CCDLANE_LANES", &lane);
    if (frame % 10 == 0) bus.publish("CCDLANE_STATUS", &status);
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

// What a monitor started for 2.5 s prints while `status` (camera streaming) is published
// with lane messages; "" when the bus cannot be had (the caller skips).
std::string live_lines_with(status_t status, const LaneEstimate& lane = {}) {
  test::TempDir dir;
  test::ChildProcess monitor({kTool, "monitor", "--lcm", kUrl, "--seconds", "2.5"},
                             test::ChildOptions{{}, dir.file("out"), dir.file("err"), {}});
  lcm::LCM bus(kUrl);
  EXPECT_TRUE(bus.good());
  status.camera_state = status_t::CAMERA_STREAMING;
  publish_for_monitor(bus, status, lane);
  const auto exit_status = monitor.wait_exit(3000);
  EXPECT_TRUE(exit_status.has_value());
  if (exit_status) {
    EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << test::read_file(dir.file("err"));
  }
  return test::read_file(dir.file("out"));
}

// The lane filter's heading and the mount's yaw it learnt (a camera yawed on the car reads
// as a heading in every solve) are on the line while the warning is available.
TEST(MonitorCommandAlone, TheLiveLineShowsTheFiltersHeadingAndTheMountsYaw) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  LaneEstimate lane;
  lane.heading_deg = -1.34;
  lane.ldw.available = true;
  lane.ldw.tracked = true;
  lane.ldw.heading_deg = 0.02;
  lane.ldw.heading_bias_deg = -1.36;
  const std::string out = live_lines_with(status_t{}, lane);
  EXPECT_NE(out.find("heading -1.34 deg, radius "), std::string::npos) << out;
  EXPECT_NE(out.find(" m/s, heading 0.02 deg (mount yaw -1.36) | camera "), std::string::npos) << out;
}

// The gyro's reconnect count comes from the status message, and only when there is a gyro.
TEST(MonitorCommandAlone, TheLiveLineShowsTheGyroReconnects) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  status_t status{};
  status.gyro_state = status_t::GYRO_OK;
  status.gyro_reconnects_total = 3;
  const std::string out = live_lines_with(status);
  EXPECT_NE(out.find("| camera streaming, gyro ok, gyro reconnects 3, vehicle none, p99 "), std::string::npos) << out;
}

// A broken vehicle gateway and gyro: the fault and the refusals by cause, from status.
TEST(MonitorCommandAlone, TheLiveLineShowsVehicleAndGyroRefusals) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  status_t status{};
  status.gyro_state = status_t::GYRO_STALE;
  status.gyro_refused_total = 40;
  status.vehicle_state = status_t::VEHICLE_FAULT;
  status.vehicle_refused_by_cause[status_t::VEHICLE_REFUSED_SPEED] = 12;
  status.vehicle_refused_by_cause[status_t::VEHICLE_REFUSED_INDICATOR] = 1;
  const std::string out = live_lines_with(status);
  EXPECT_NE(out.find(", vehicle fault (refused: speed 12, indicator 1), gyro readings refused 40, p99 "),
            std::string::npos)
      << out;
}

// The online calibration from the status message: in the live line and, with --json, in
// a {"status": ...} object.
TEST(MonitorCommandAlone, TheCalibrationIsShownInTheLiveLineAndAsJson) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir dir;
  test::ChildProcess text({kTool, "monitor", "--lcm", kUrl, "--seconds", "2.5"},
                          test::ChildOptions{{}, dir.file("text"), dir.file("text.err"), {}});
  test::ChildProcess json({kTool, "monitor", "--lcm", kUrl, "--seconds", "2.5", "--json"},
                          test::ChildOptions{{}, dir.file("json"), dir.file("json.err"), {}});
  lcm::LCM bus(kUrl);
  ASSERT_TRUE(bus.good());
  status_t status{};
  status.camera_state = status_t::CAMERA_STREAMING;
  status.calibration_state = status_t::CALIBRATION_CALIBRATING;
  status.calibration_progress = 0.45;
  status.calibration_yaw_deg = 0.25;
  status.calibration_pitch_deg = -0.5;
  status.calibration_yaw_estimate_deg = 1.5;
  status.calibration_frames_total = 405;
  publish_for_monitor(bus, status);
  ASSERT_TRUE(text.wait_exit(3000).has_value());
  ASSERT_TRUE(json.wait_exit(3000).has_value());
  const std::string out = test::read_file(dir.file("text"));
  EXPECT_NE(out.find("| calibration calibrating 45%, yaw +0.25 pitch -0.50 deg"), std::string::npos) << out;
  int statuses = 0;
  for (const std::string& line : lines_of(test::read_file(dir.file("json")))) {
    const Json j = Json::parse(line);
    if (!j.contains("status")) continue;
    ++statuses;
    const Json& c = j["status"]["calibration"];
    EXPECT_EQ(c["state"], "calibrating");
    EXPECT_EQ(c["progress"], 0.45);
    EXPECT_EQ(c["yaw_deg"], 0.25);
    EXPECT_EQ(c["pitch_deg"], -0.5);
    EXPECT_EQ(c["yaw_estimate_deg"], 1.5);
    EXPECT_EQ(c["frames"], 405);
  }
  EXPECT_GE(statuses, 1);
}

TEST(MonitorCommandAlone, NothingOnTheBusIsExitOneWithOneLine) {
  const auto r = test::run_process({kTool, "monitor", "--lcm", "memq://", "--seconds", "0.3"});
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_EQ(r.err, "ccdlane: no lane messages on CCDLANE_LANES (memq://) within 0.3 s\n");
}

TEST(MonitorCommandAlone, BadUsageIsExitTwo) {
  const auto r = test::run_process({kTool, "monitor", "--count", "0"});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(lines_of(r.err).size(), 1u) << r.err;
  EXPECT_EQ(r.err, "ccdlane: --count: must be a number greater than 0, got 0 (see ccdlane --help)\n");
  const auto s = test::run_process({kTool, "monitor", "--seconds", "-1"});
  EXPECT_EQ(s.exit_status, 2);
  EXPECT_EQ(s.err, "ccdlane: --seconds: must be a number greater than 0, got -1 (see ccdlane --help)\n");
  // LCM's tcpq client once aborted monitor 2 s after start (exit 134) without its server.
  const auto t = test::run_process({kTool, "monitor", "--lcm", "tcpq://192.0.2.1:7700", "--seconds", "3"});
  EXPECT_EQ(t.exit_status, 2);
  EXPECT_EQ(t.err,
            "ccdlane: --lcm: tcpq:// is not supported (LCM's tcpq client aborts the process when its server is "
            "unreachable); use udpm://, memq:// or file://\n");
}

}  // namespace
}  // namespace ccdlane
