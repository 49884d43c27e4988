// ccdlaned end to end on a real multicast bus in a private network namespace: rendered
// frames in, one lane message per frame out, the same estimates as `ccdlane replay`;
// rendered colour roads from a GigE Vision camera in a Bayer format and from a V4L2
// camera in YUYV to ok lanes; the
// gyro emulator hanging up mid-run without the lane messages stopping; and a GigE Vision
// camera that stops sending (the simulator frozen) silencing the watchdog until the
// driver has reconnected.
#include <arv.h>
#include <linux/videodev2.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <ccdlane/status_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "app/config.hpp"
#include "bus/lane_message.hpp"
#include "core/synth/road_renderer.hpp"
#include "core/synth/synth_drive.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/notify_socket.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/drivers/camera/fake_v4l2/fake_v4l2_device.hpp"
#include "tests/drivers/camera/private_namespace.hpp"
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
      +[](const lcm::ReceiveBuffer*, const std::string&, const lane_estimate_t* m, Received* g) {
        g->lanes.push_back(*m);
      },
      &got);
  bus.subscribeFunction(
      "CCDLANE_STATUS",
      +[](const lcm::ReceiveBuffer*, const std::string&, const status_t* m, Received* g) { g->statuses.push_back(*m); },
      &got);
}

// Each test in its own private network namespace (a hermetic udpm bus), subscribed to
// the daemon's lane and status channels.
class CcdlanedEndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
    bus_ = std::make_unique<lcm::LCM>(kUrl);
    ASSERT_TRUE(bus_->good());
    subscribe(*bus_, got);
  }
  std::unique_ptr<lcm::LCM> bus_;
  Received got;
};

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
    for (std::size_t i = 0; i < daemon.size(); ++i)
      expect_same(daemon[i], replay[i], where + "[" + std::to_string(i) + "]");
  } else {
    EXPECT_EQ(daemon, replay) << where;
  }
}

// The daemon on a frame directory (no gyro device: the frames.csv columns give the
// priors, as in replay), paced fast and not looping: it stops by itself at the end.
TEST_F(CcdlanedEndToEnd, FramesSourceGivesOneMessagePerFrameMatchingReplay) {
  lcm::LCM& bus = *bus_;

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
    expect_same(cli::lane_estimate_json(from_message(m)), expected[static_cast<std::size_t>(i)],
                "frame " + std::to_string(i));
    ok += m.ok;
  }
  EXPECT_GE(ok, kFrames - 2) << "the synthetic road is an easy one";
  ASSERT_FALSE(got.statuses.empty());
  EXPECT_EQ(got.statuses.back().allocations_since_ready, 0);
  EXPECT_EQ(got.statuses.back().frames_dropped_total, 0);
}

// The 3DM-GX1 emulator (another process, on a pty behind a link) hangs up every 1.3 s
// for 300 ms: frames keep being processed and published throughout, the status counts
// the hang-ups and the reconnects, and the gyro comes back.
TEST_F(CcdlanedEndToEnd, GyroHangUpsDoNotStopTheLaneMessages) {
  lcm::LCM& bus = *bus_;

  test::TempDir dir;
  const std::string frames = render(dir, 20, {"--no-gyro"});  // the gyro device is the only source of priors
  const std::string link = dir.file("gx1");
  test::ChildProcess emulator(
      {kTool, "gx1-emulate", "--link", link, "--attitude", "0,-3,0", "--hangup-every", "1.3", "--hangup-ms", "300"},
      test::ChildOptions{{}, dir.file("emulator.out"), dir.file("emulator.err"), {}});
  struct stat st {};
  for (int i = 0; i < 100 && lstat(link.c_str(), &st) != 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  ASSERT_EQ(lstat(link.c_str(), &st), 0) << test::read_file(dir.file("emulator.err"));

  const std::string config =
      dir.write("daemon.toml", "[source]\nkind = \"frames\"\npath = \"" + frames +
                                   "\"\nrate_hz = 50\nloop = true\n[gyro]\ndevice = \"" + link + "\"\n");
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
  // Each hang-up the session recovered from is one reconnect (the last may still be under way).
  EXPECT_GE(last.gyro_reconnects_total, 2) << log;
  EXPECT_LE(last.gyro_reconnects_total, last.gyro_errors_total) << log;
  EXPECT_EQ(last.allocations_since_ready, 0);
  // Some frames had the gyro's priors and some (while it was away) had none; status ticks
  // and hang-ups both come about once a second, so the state seen at ticks is no proof.
  EXPECT_GT(last.gyro_samples_total, 0);
  EXPECT_GT(last.no_attitude_total, 0) << log;
  EXPECT_LT(last.no_attitude_total, last.frames_processed_total) << log;
}

int count_equal(const std::vector<std::string>& v, const std::string& what) {
  return static_cast<int>(std::count(v.begin(), v.end(), what));
}

// Aravis' GigE Vision camera simulator (the camera of the driver's own tests) is frozen
// with SIGSTOP for 3 s: the driver sees no frame and gives the camera up (releasing it
// blocks in Aravis until the frozen camera answers or times out), the status says the
// camera is stalled and systemd's watchdog hears nothing; after SIGCONT the driver
// reconnects, WATCHDOG=1 comes back and so do the lane messages.
TEST_F(CcdlanedEndToEnd, AStalledCameraSilencesTheWatchdogUntilItIsBack) {
  lcm::LCM& bus = *bus_;

  test::TempDir dir;
  test::ChildProcess camera({"/usr/bin/arv-fake-gv-camera-0.8", "-i", "127.0.0.1"},
                            test::ChildOptions{{}, dir.file("camera.out"), dir.file("camera.err"), {}});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // until it listens
  // No gyro: a roll prior makes the free set well-posed. The fake's diagonal ramp shows
  // no lanes, so the messages say ok = false with a reason; they still come one a frame.
  const std::string config = dir.write("daemon.toml",
                                       "[source]\nkind = \"aravis\"\ncamera = \"127.0.0.1\"\nrate_hz = 30\n"
                                       "[prior]\nphi_deg = [0.0, 1.0]\n[daemon]\nstall_timeout_s = 1.0\n");
  test::NotifySocket notify(dir.file("notify"));
  test::ChildProcess daemon(
      {kDaemon, "--config", config},
      test::ChildOptions{{"NOTIFY_SOCKET=" + notify.path(), "WATCHDOG_USEC=300000"}, "", dir.file("stderr"), {}});
  const auto log = [&] { return test::read_file(dir.file("stderr")); };
  // Notifications while the bus is served, so that lane messages are not lost meanwhile.
  const auto notifications_for = [&](std::chrono::milliseconds span) {
    std::vector<std::string> all;
    const auto end = Clock::now() + span;
    while (Clock::now() < end) {
      bus.handleTimeout(20);
      for (std::string& m : notify.drain()) all.push_back(std::move(m));
    }
    return all;
  };
  const auto has_status_with = [](const std::vector<std::string>& v, const std::string& what) {
    return std::any_of(v.begin(), v.end(), [&](const std::string& m) {
      return m.rfind("STATUS=", 0) == 0 && m.find(what) != std::string::npos;
    });
  };

  std::vector<std::string> before;
  const auto ready_by = Clock::now() + std::chrono::seconds(15);
  while (count_equal(before, "READY=1") == 0 && Clock::now() < ready_by)
    for (std::string& m : notifications_for(std::chrono::milliseconds(100))) before.push_back(std::move(m));
  ASSERT_EQ(count_equal(before, "READY=1"), 1) << log();
  before = notifications_for(std::chrono::milliseconds(1200));
  EXPECT_GE(count_equal(before, "WATCHDOG=1"), 3) << "pinged (every 100 ms) while frames flow";
  const std::size_t lanes_before_stall = got.lanes.size();
  ASSERT_GT(lanes_before_stall, 20u) << log();

  camera.signal(SIGSTOP);
  notifications_for(std::chrono::milliseconds(300));  // frames already on their way
  const std::size_t lanes_at_stall = got.lanes.size();
  const std::vector<std::string> stalled = notifications_for(std::chrono::milliseconds(2700));
  EXPECT_EQ(count_equal(stalled, "WATCHDOG=1"), 0) << "no frames, no watchdog pings";
  std::string statuses;
  for (const std::string& m : stalled) statuses += m.rfind("STATUS=", 0) == 0 ? m + "\n" : "";
  EXPECT_TRUE(has_status_with(stalled, "STATUS=recovering ") || has_status_with(stalled, "STATUS=stalled "))
      << statuses << log();
  // Why depends on how far the driver got: stuck releasing the camera ("no frame for
  // 1.3 s (the capture call has not returned)"), or already failing to reopen it.
  EXPECT_TRUE(has_status_with(stalled, "; camera: ")) << "the status says why: " << statuses;
  EXPECT_EQ(got.lanes.size(), lanes_at_stall) << "no lane messages without frames";
  ASSERT_FALSE(got.statuses.empty());
  const status_t& during = got.statuses.back();
  EXPECT_TRUE(during.camera_state == status_t::CAMERA_RECOVERING || during.camera_state == status_t::CAMERA_STALLED)
      << static_cast<int>(during.camera_state);
  EXPECT_FALSE(during.camera_problem.empty());

  camera.signal(SIGCONT);
  // The simulator hands control to a new client once the old one's heartbeat has expired
  // (3 s); the driver retries with backoff meanwhile.
  std::vector<std::string> after;
  const auto back_by = Clock::now() + std::chrono::seconds(20);
  while (count_equal(after, "WATCHDOG=1") < 3 && Clock::now() < back_by)
    for (std::string& m : notifications_for(std::chrono::milliseconds(100))) after.push_back(std::move(m));
  EXPECT_GE(count_equal(after, "WATCHDOG=1"), 3) << "pings again once frames flow: " << log();
  for (std::string& m : notifications_for(std::chrono::milliseconds(1100))) after.push_back(std::move(m));
  EXPECT_TRUE(has_status_with(after, "STATUS=streaming ")) << log();
  EXPECT_GT(got.lanes.size(), lanes_at_stall + 20) << "lane messages continue: " << log();

  daemon.signal(SIGTERM);
  const auto exit_status = daemon.wait_exit(2000);
  while (bus.handleTimeout(100) > 0) {
  }
  ASSERT_TRUE(exit_status.has_value()) << log();
  EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << log();
  const status_t& last = got.statuses.back();
  EXPECT_GE(last.source_reconnects_total, 1) << log();
  EXPECT_EQ(last.allocations_since_ready, 0) << "reconnecting allocates inside Aravis (malloc), not in ccdlaned";
  EXPECT_NE(log().find("aravis:127.0.0.1: no frame for 1000 ms; reopening"), std::string::npos) << log();
  EXPECT_NE(log().find("streaming again"), std::string::npos) << log();
}

}  // namespace
}  // namespace ccdlane

namespace ccdlane {
namespace {

// The default drive's road in colour, as `ccdlane synth` renders it with colour = true.
std::vector<std::vector<std::uint8_t>> colour_road(const Config& c, int frames) {
  std::vector<std::vector<std::uint8_t>> rgb;
  SynthDrive drive(c.synth, c.nominal_pose());
  RoadRenderer renderer(c.camera, c.synth);
  for (int k = 0; k < frames; ++k) {
    rgb.emplace_back(static_cast<std::size_t>(c.camera.Nu) * c.camera.Nv * 3);
    renderer.render(
        drive.frame(static_cast<std::uint64_t>(k) * 3),
        MutableImageView{rgb.back().data(), c.camera.Nu, c.camera.Nv, c.camera.Nu * 3, PixelFormat::rgb8, 8});
  }
  return rgb;
}

// Runs ccdlaned on `source` (a [source] table's body) until `messages` lane messages have
// come, then stops it; nearly all must be ok (the easy synthetic road: the frame-directory
// test above has all but two frames ok), with the lane's true width. Returns the log.
std::string expect_ok_lanes(lcm::LCM& bus, Received& got, const Config& c, const std::string& source) {
  test::TempDir dir;
  // No gyro: a roll prior makes the free set well-posed (as for the stalled camera above).
  const std::string config = dir.write("daemon.toml", "[source]\n" + source + "[prior]\nphi_deg = [0.0, 1.0]\n");
  test::ChildProcess daemon({kDaemon, "--config", config}, test::ChildOptions{{}, "", dir.file("stderr"), {}});
  const auto log = [&] { return test::read_file(dir.file("stderr")); };
  constexpr std::size_t kMessages = 30;
  const auto end = Clock::now() + std::chrono::seconds(30);
  while (got.lanes.size() < kMessages && Clock::now() < end) bus.handleTimeout(100);
  daemon.signal(SIGTERM);
  const auto exit_status = daemon.wait_exit(5000);
  while (bus.handleTimeout(100) > 0) {
  }
  EXPECT_TRUE(exit_status.has_value()) << log();
  if (exit_status) {
    EXPECT_EQ(WEXITSTATUS(*exit_status), 0) << log();
  }
  EXPECT_GE(got.lanes.size(), kMessages) << log();
  int ok = 0;
  for (const lane_estimate_t& m : got.lanes) {
    if (!m.ok) continue;
    ++ok;
    EXPECT_GE(m.num_lines, 2);
    EXPECT_NEAR(m.lane_width_mm, c.synth.lane_width_mm, 0.05 * c.synth.lane_width_mm) << "frame " << m.frame;
  }
  EXPECT_GE(ok, static_cast<int>(got.lanes.size()) - 2) << log();
  return log();
}

// Rendered colour frames of the default drive, served by Aravis' fake camera as BayerRG8
// through its fill-pattern hook (its own pattern is a ramp, no road).
struct BayerRoad {
  int width = 0, height = 0;
  std::vector<std::vector<std::uint8_t>> rgb;
  std::atomic<int> served{0};
  std::atomic<int> wrong_format{0};

  // PFNC BayerRG8: R G / G B from the top-left pixel (written here, not by the fake,
  // whose own RG8 and BG8 are swapped: tests/drivers/camera/aravis_camera_test.cpp).
  static void fill(ArvBuffer* buffer, void* self_ptr, guint32, guint32, ArvPixelFormat format) {
    auto* self = static_cast<BayerRoad*>(self_ptr);
    // The buffer holds the camera's payload (width x height bytes at 8 bits a pixel); the
    // size Aravis reports is what was filled, 0 until a pattern has run.
    auto* data = static_cast<std::uint8_t*>(const_cast<void*>(arv_buffer_get_data(buffer, nullptr)));
    const int w = arv_buffer_get_image_width(buffer), h = arv_buffer_get_image_height(buffer);
    if (format != ARV_PIXEL_FORMAT_BAYER_RG_8 || w != self->width || h != self->height || data == nullptr) {
      ++self->wrong_format;
      return;
    }
    const std::vector<std::uint8_t>& frame = self->rgb[static_cast<std::size_t>(self->served++) % self->rgb.size()];
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int channel = (y % 2 == 0) ? (x % 2 == 0 ? 0 : 1) : (x % 2 == 0 ? 1 : 2);
        data[static_cast<std::size_t>(y) * w + x] = frame[(static_cast<std::size_t>(y) * w + x) * 3 + channel];
      }
  }
};

// A GigE Vision camera (Aravis' simulator, run in this process on loopback) sends
// rendered colour frames of the default road as BayerRG8; ccdlaned asks for that format
// ([source] device_format), demosaics, detects on the paint measure and publishes lane
// messages. The road is the easy synthetic one (the frame-directory test above: all but
// two frames ok), so nearly every message must be ok with the lane's true width.
TEST_F(CcdlanedEndToEnd, BayerFramesFromAGigECameraGiveOkLanes) {
  Config c = default_config();
  c.synth.colour = true;
  BayerRoad road;
  road.width = c.camera.Nu;
  road.height = c.camera.Nv;
  road.rgb = colour_road(c, 12);
  ArvGvFakeCamera* camera = arv_gv_fake_camera_new("127.0.0.1", "CCDLANE01");
  ASSERT_NE(camera, nullptr);
  const std::unique_ptr<ArvGvFakeCamera, void (*)(ArvGvFakeCamera*)> owned(
      camera, [](ArvGvFakeCamera* p) { g_object_unref(p); });
  ASSERT_TRUE(arv_gv_fake_camera_is_running(camera)) << "the GigE Vision simulator did not start on 127.0.0.1";
  arv_fake_camera_set_fill_pattern(arv_gv_fake_camera_get_fake_camera(camera), &BayerRoad::fill, &road);

  const std::string log = expect_ok_lanes(*bus_, got, c,
                                          "kind = \"aravis\"\ncamera = \"127.0.0.1\"\nrate_hz = 20\n"
                                          "pixel_format = \"colour\"\ndevice_format = \"BayerRG8\"\n");
  EXPECT_NE(log.find("BayerRG8"), std::string::npos) << "the camera was opened in Bayer: " << log;
  EXPECT_EQ(road.wrong_format.load(), 0) << "every frame asked of the camera was BayerRG8 at the road's size";
}

// The same road from a V4L2 camera in YUYV (BT.601 limited range, as the driver reads it):
// the FUSE fake device, in a private mount namespace (root), serving the rendered frames.
TEST_F(CcdlanedEndToEnd, YuyvFramesFromAV4l2CameraGiveOkLanes) {
  if (const std::string why = test::enter_private_mount_namespace(); !why.empty()) GTEST_SKIP() << why;
  Config c = default_config();
  c.synth.colour = true;
  test::FakeV4l2Options options{.formats = {V4L2_PIX_FMT_YUYV}, .sizes = {{c.camera.Nu, c.camera.Nv}}, .fps = 20.0};
  for (const std::vector<std::uint8_t>& rgb : colour_road(c, 12)) {
    std::vector<std::uint8_t> yuyv(rgb.size() / 3 * 2);
    for (std::size_t p = 0; p + 1 < rgb.size() / 3; p += 2) {
      const std::uint8_t* a = &rgb[3 * p];
      const std::uint8_t* b = a + 3;
      auto y = [](const std::uint8_t* q) {
        return static_cast<std::uint8_t>(16 + ((66 * q[0] + 129 * q[1] + 25 * q[2] + 128) >> 8));
      };
      const int r = (a[0] + b[0] + 1) / 2, g = (a[1] + b[1] + 1) / 2, bl = (a[2] + b[2] + 1) / 2;
      yuyv[2 * p] = y(a);
      yuyv[2 * p + 1] = static_cast<std::uint8_t>(128 + ((-38 * r - 74 * g + 112 * bl + 128) >> 8));
      yuyv[2 * p + 2] = y(b);
      yuyv[2 * p + 3] = static_cast<std::uint8_t>(128 + ((112 * r - 94 * g - 18 * bl + 128) >> 8));
    }
    options.frames.push_back(std::move(yuyv));
  }
  test::TempDir dev;
  test::FakeV4l2Device camera(dev.file("video0"), options);
  const std::string log = expect_ok_lanes(
      *bus_, got, c, "kind = \"v4l2\"\ndevice = \"" + camera.path() + "\"\nrate_hz = 20\npixel_format = \"colour\"\n");
  EXPECT_NE(log.find("YUYV"), std::string::npos) << "the camera was opened in YUYV: " << log;
}

}  // namespace
}  // namespace ccdlane
