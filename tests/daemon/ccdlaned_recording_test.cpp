// A drive recorded from the running daemon replays to the lane estimates the daemon
// published: ccdlaned (synthetic road, the emulated 3DM-GX1 on a pty as its live gyro,
// [lcm] publish_frames) on a real multicast bus in a private network namespace, the real
// lcm-logger recording that bus, then `ccdlane replay CONFIG LOG.lcmlog` compared frame by
// frame (by sequence number) with the lane messages in the same log.
//
// Tolerance: none. Both programs run the same LaneEstimator object code (ccdlane::lane,
// one build) on the same inputs: the pixels and the gyro angles the daemon used travel
// bit for bit in frame_t (LCM doubles are IEEE 754 big-endian), with its sequence number
// and frame time; the estimator has no threads and no clock of its own, and its tracking
// state evolves over the same frames in the same order, because frames are published
// from the processing thread after any drop. The JSON printer writes the shortest digits
// that read back to the same double, so a replayed number equals the published one
// exactly; any difference is a real difference in input or state.
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <chrono>
#include <map>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/frame_t.hpp>
#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "app/config_loader.hpp"
#include "bus/channels.hpp"
#include "bus/lane_message.hpp"
#include "core/synth/synth_drive.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"
#include "tools/ccdlane/lane_estimate_json.hpp"

namespace ccdlane {
namespace {

using nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

const std::string kUrl = test::kBusUrl;
const std::string kDaemon = CCDLANE_DAEMON, kTool = CCDLANE_TOOL;
// Raw frames (~0.5 MB) are all dropped by the default receive buffer (platform-notes.md).
const std::string kRecordingUrl = kUrl + "&recv_buf_size=8388608";

// What the log holds on ccdlane's channels.
struct Recorded {
  struct Frame {
    std::int64_t sequence, t_ns;
    bool has_gyro;
  };
  std::vector<Frame> frames;
  std::vector<lane_estimate_t> lanes;
  std::vector<status_t> statuses;
  std::size_t other_events = 0;
};

Recorded read_log(const std::string& path) {
  Recorded r;
  lcm::LogFile log(path, "r");
  EXPECT_TRUE(log.good()) << path;
  if (!log.good()) return r;
  const std::string frames = channel_name("CCDLANE_", Channel::frames);
  const std::string lanes = channel_name("CCDLANE_", Channel::lanes);
  const std::string status = channel_name("CCDLANE_", Channel::status);
  for (const lcm::LogEvent* e; (e = log.readNextEvent()) != nullptr;) {
    if (e->channel == frames) {
      frame_t m;
      EXPECT_GE(m.decode(e->data, 0, static_cast<int>(e->datalen)), 0);
      r.frames.push_back({m.sequence, m.t_ns, m.has_gyro != 0});
    } else if (e->channel == lanes) {
      EXPECT_GE(r.lanes.emplace_back().decode(e->data, 0, static_cast<int>(e->datalen)), 0);
    } else if (e->channel == status) {
      EXPECT_GE(r.statuses.emplace_back().decode(e->data, 0, static_cast<int>(e->datalen)), 0);
    } else {
      ++r.other_events;
    }
  }
  return r;
}

off_t file_size(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 ? st.st_size : -1;
}

// The fields of docs/interfaces.md's per-frame result, in its order.
void expect_interfaces_md_shape(const ordered_json& j) {
  std::vector<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.push_back(key);
  std::vector<std::string> want = {"frame", "t_ns", "ok"};
  if (!j.value("ok", false)) want.push_back("reason");
  want.push_back("state");
  for (const char* k :
       {"psi_deg", "theta_deg", "phi_deg", "H_mm", "lines", "lane_width_mm", "lateral_offset_mm", "heading_deg",
        "curvature_per_m", "radius_of_curvature_m", "departure", "rms_px", "iterations", "latency_us", "ldw"})
    want.push_back(k);
  EXPECT_EQ(keys, want) << j;
  ASSERT_TRUE(j["lines"].is_array()) << j;
  for (const ordered_json& line : j["lines"]) {
    std::vector<std::string> line_keys;
    for (const auto& [key, value] : line.items()) line_keys.push_back(key);
    EXPECT_EQ(line_keys,
              (std::vector<std::string>{"id", "y0_mm", "m", "c_per_mm", "marks", "confidence", "near_mm", "far_mm"}))
        << j;
  }
  const std::string departure = j["departure"].get<std::string>();
  EXPECT_TRUE(departure == "none" || departure == "left" || departure == "right") << j;
}

TEST(CcdlanedRecording, WhatLcmLoggerRecordsOfTheDaemonReplaysToTheEstimatesItPublished) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir dir;
  // The demo drive at 100 Hz with a queue of one: frames that come while the estimator
  // is busy (its cold start, a loaded machine) are dropped, and the log must then hold
  // the frames it processed, not the ones captured.
  const std::string config = dir.write("drive.toml",
                                       "[source]\nkind = \"synth\"\nrate_hz = 100\n"
                                       "[synth]\nframes = 40\n"
                                       "[gyro]\ndevice = \"emulated\"\n"
                                       "[daemon]\nqueue_depth = 1\n"
                                       "[lcm]\nurl = \"" +
                                           kUrl + "\"\npublish_frames = true\n");
  const std::string log = dir.file("drive.lcmlog");

  // lcm-logger first, and listening (its file grows) before the daemon's first frame: a
  // replay starts from the daemon's first frame, as the daemon's tracking did.
  test::ChildProcess logger({"/usr/bin/lcm-logger", "--lcm-url=" + kRecordingUrl, log},
                            {{}, dir.file("logger.out"), dir.file("logger.err"), {}});
  {
    lcm::LCM probe(kUrl);
    ASSERT_TRUE(probe.good());
    const auto end = Clock::now() + std::chrono::seconds(10);
    const char byte = 0;
    while (file_size(log) <= 0 && Clock::now() < end) {
      probe.publish("TEST_PROBE", &byte, 1);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    ASSERT_GT(file_size(log), 0) << "lcm-logger did not record within 10 s: "
                                 << test::read_file(dir.file("logger.err"));
  }

  // The daemon, until it has published enough lane messages.
  lcm::LCM bus(kUrl);
  ASSERT_TRUE(bus.good());
  int published = 0;
  bus.subscribeFunction(
      channel_name("CCDLANE_", Channel::lanes),
      +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t*, int* n) { ++*n; }, &published);
  test::ChildProcess daemon({kDaemon, "--config", config}, {{}, "", dir.file("daemon.err"), {}});
  constexpr int kEnough = 60;
  const auto end = Clock::now() + std::chrono::seconds(60);
  while (published < kEnough && Clock::now() < end && !daemon.wait_exit(0)) bus.handleTimeout(50);
  ASSERT_GE(published, kEnough) << test::read_file(dir.file("daemon.err"));
  daemon.signal(SIGTERM);
  const std::optional<int> daemon_status = daemon.wait_exit(10'000);
  ASSERT_TRUE(daemon_status.has_value()) << "ccdlaned did not stop on SIGTERM";
  EXPECT_TRUE(WIFEXITED(*daemon_status) && WEXITSTATUS(*daemon_status) == 0) << test::read_file(dir.file("daemon.err"));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last status reaches the logger
  logger.signal(SIGINT);
  const std::optional<int> logger_status = logger.wait_exit(10'000);
  ASSERT_TRUE(logger_status.has_value()) << "lcm-logger did not stop on SIGINT";
  EXPECT_TRUE(WIFEXITED(*logger_status) && WEXITSTATUS(*logger_status) == 0) << test::read_file(dir.file("logger.err"));

  // The log: every processed frame, and its lane message, none lost on the bus.
  const Recorded rec = read_log(log);
  ASSERT_FALSE(rec.statuses.empty());
  const status_t& last = rec.statuses.back();
  ASSERT_EQ(rec.lanes.size(), static_cast<std::size_t>(last.frames_processed_total))
      << "lcm-logger missed lane messages";
  ASSERT_EQ(rec.frames.size(), rec.lanes.size()) << "lcm-logger missed frames (receive buffer?)";
  std::size_t without_gyro = 0;
  for (std::size_t i = 0; i < rec.frames.size(); ++i) {
    ASSERT_EQ(rec.frames[i].sequence, rec.lanes[i].frame) << "frame and lane message " << i;
    EXPECT_EQ(rec.frames[i].t_ns, rec.lanes[i].t_ns) << "frame " << rec.frames[i].sequence;
    without_gyro += !rec.frames[i].has_gyro;
  }
  // Sequences missing from the log are frames the daemon dropped (it may drop a few more
  // after its last processed frame, or leave them queued at the stop).
  const auto missing =
      static_cast<std::int64_t>(rec.frames.back().sequence + 1) - static_cast<std::int64_t>(rec.frames.size());
  EXPECT_LE(missing, last.frames_dropped_total);
  // "The lack of one" travels too: frames without a prior are the daemon's no_attitude count.
  EXPECT_EQ(without_gyro, static_cast<std::size_t>(last.no_attitude_total));
  EXPECT_LT(without_gyro, rec.frames.size() / 2) << "the live gyro gave most frames their prior";
  // Frame times are the synthetic drive's own clock, as `ccdlane synth` stamps frame n.
  const Config drive_config = load_config_file(config);
  const SynthDrive drive(drive_config.synth, drive_config.nominal_pose());
  for (const lane_estimate_t& m : rec.lanes)
    ASSERT_EQ(m.t_ns, drive.t_ns(static_cast<std::uint64_t>(m.frame))) << "frame " << m.frame;

  // The replay, from the file alone.
  const auto replay = test::run_process({kTool, "replay", config, log});
  ASSERT_EQ(replay.exit_status, 0) << replay.err;
  std::map<std::int64_t, const lane_estimate_t*> published_by_frame;
  for (const lane_estimate_t& m : rec.lanes) published_by_frame[m.frame] = &m;
  std::istringstream lines(replay.out);
  std::size_t compared = 0, ok = 0;
  std::int64_t previous = -1;
  for (std::string line; std::getline(lines, line);) {
    ordered_json replayed = ordered_json::parse(line);
    expect_interfaces_md_shape(replayed);
    const std::int64_t frame = replayed["frame"].get<std::int64_t>();
    EXPECT_GT(frame, previous) << "in the daemon's order";
    previous = frame;
    const auto it = published_by_frame.find(frame);
    ASSERT_NE(it, published_by_frame.end()) << "replayed frame " << frame << " was never published";
    ordered_json expected = cli::lane_estimate_json(from_message(*it->second));
    replayed.erase("latency_us");  // the clocks of two runs
    expected.erase("latency_us");
    EXPECT_EQ(replayed.dump(), expected.dump()) << "frame " << frame;
    ++compared;
    ok += replayed["ok"].get<bool>();
  }
  EXPECT_EQ(compared, rec.lanes.size()) << "one replayed line per recorded frame: " << replay.err;
  EXPECT_GE(ok, compared * 9 / 10) << "real estimates are compared";
  EXPECT_NE(replay.err.find(std::to_string(compared) + " frames, "), std::string::npos) << replay.err;
  RecordProperty("frames", static_cast<int>(compared));
  RecordProperty("dropped", static_cast<int>(last.frames_dropped_total));
  std::printf(
      "recorded %zu processed frames (%lld dropped by the daemon, %lld of them before the last processed "
      "one; %zu without a gyro prior); replayed %zu, %zu ok\n",
      compared, static_cast<long long>(last.frames_dropped_total), static_cast<long long>(missing), without_gyro,
      compared, ok);
}

}  // namespace
}  // namespace ccdlane
