// The V4L2 driver on its real syscall path (open, ioctl, mmap, poll) against a fake camera
// served by FUSE in a private mount namespace: intact numbered frames in each format,
// refusals that say what the device offered, controls, drop counting, stall restart,
// unplug and return. Plus a run against a real /dev/video* where one exists.
#include "drivers/camera/v4l2_camera.hpp"

#include <linux/videodev2.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "drivers/camera/frame_pool.hpp"
#include "tests/drivers/camera/fake_v4l2/fake_v4l2_device.hpp"
#include "tests/drivers/camera/private_namespace.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

// Before main: unshare() needs a single-threaded process.
const std::string g_namespace_problem = test::enter_private_mount_namespace();

class V4l2CameraTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!g_namespace_problem.empty()) GTEST_SKIP() << g_namespace_problem;
    if (access("/dev/fuse", R_OK | W_OK) != 0) GTEST_SKIP() << "no usable /dev/fuse";
  }
  std::unique_ptr<test::FakeV4l2Device> serve(test::FakeV4l2Options options) {
    return std::make_unique<test::FakeV4l2Device>(dir_.file("video0"), std::move(options));
  }
  CameraSettings settings(PixelFormat format = PixelFormat::mono8, double fps = 60) const {
    CameraSettings s;
    s.width = 800;
    s.height = 600;
    s.format = format;
    s.fps = fps;
    s.buffer_count = 4;
    return s;
  }
  // Captures until a frame arrives or `deadline_ms` passes.
  static CaptureStatus next_frame(V4l2Camera& cam, const MutableImageView& into, FrameMeta& meta, int deadline_ms) {
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(deadline_ms);
    CaptureStatus s = CaptureStatus::timeout;
    while (std::chrono::steady_clock::now() < end)
      if ((s = cam.capture(into, meta, 200)) == CaptureStatus::frame) break;
    return s;
  }
  test::TempDir dir_;
};

// Every pixel of the frame is the one the fake wrote for that sequence number.
::testing::AssertionResult frame_is_intact(const ImageView& v, std::uint64_t sequence) {
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) {
      const std::uint16_t want = v.format == PixelFormat::mono8
                                     ? test::fake_pixel8(static_cast<std::uint32_t>(sequence), x, y)
                                     : test::fake_pixel16(static_cast<std::uint32_t>(sequence), x, y);
      if (v.at(x, y) != want)
        return ::testing::AssertionFailure()
               << "frame " << sequence << " pixel (" << x << "," << y << ") is " << v.at(x, y) << ", expected " << want;
    }
  return ::testing::AssertionSuccess();
}

// Returns the sequence gaps seen: frames the fake had no free buffer for (a loaded
// machine can starve the consumer for a few frame periods).
std::uint64_t expect_stream_intact(V4l2Camera& cam, FramePool& pool, int frames) {
  std::uint64_t gaps = 0;
  std::uint64_t last = 0;
  std::int64_t last_t = 0;
  for (int n = 0; n < frames; ++n) {
    const int i = pool.borrow();
    if (i < 0) {
      ADD_FAILURE() << "pool exhausted";
      return gaps;
    }
    FrameMeta& meta = pool.meta(i);
    EXPECT_EQ(cam.capture(pool.view(i), meta, 1000), CaptureStatus::frame) << cam.last_problem();
    EXPECT_TRUE(frame_is_intact(pool.view(i), meta.sequence));
    if (n > 0) {
      EXPECT_GT(meta.sequence, last);
      gaps += meta.sequence - last - 1;
      EXPECT_GT(meta.t_ns, last_t);
    }
    const std::int64_t age = monotonic_ns() - meta.t_ns;  // the fake's capture time is monotonic
    EXPECT_GE(age, 0);
    EXPECT_LT(age, 1'000'000'000);
    last = meta.sequence;
    last_t = meta.t_ns;
    EXPECT_TRUE(pool.give_back(i));
  }
  return gaps;
}

TEST_F(V4l2CameraTest, StreamsIntactGreyFrames) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
  V4l2Camera cam(fake->path(), settings());
  ASSERT_EQ(cam.open(), "");
  EXPECT_EQ(cam.state(), DeviceState::streaming);
  EXPECT_NE(cam.describe().find("800x600 GREY 60 fps, 4 buffers"), std::string::npos) << cam.describe();
  EXPECT_DOUBLE_EQ(fake->frame_rate(), 60.0);
  FramePool pool({.count = 3, .width = cam.width(), .height = cam.height(), .format = cam.format()});
  const std::uint64_t gaps = expect_stream_intact(cam, pool, 30);
  EXPECT_EQ(cam.counters().frames, 30u);
  EXPECT_EQ(cam.counters().dropped, gaps);
  EXPECT_EQ(cam.counters().errors, 0u);
  cam.close();
  EXPECT_EQ(cam.state(), DeviceState::closed);
  // The kernel sends FUSE's RELEASE in the background after close().
  for (int i = 0; i < 100 && fake->open_count() != 0; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(fake->open_count(), 0);
}

TEST_F(V4l2CameraTest, ReducesYuyvToItsLumaPlane) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_YUYV}});
  V4l2Camera cam(fake->path(), settings());
  ASSERT_EQ(cam.open(), "");
  EXPECT_NE(cam.describe().find("YUYV"), std::string::npos);
  FramePool pool({.count = 2, .width = 800, .height = 600});
  expect_stream_intact(cam, pool, 10);
}

// The fake's YUYV carries U 50, V 200 in every pair. Reference: BT.601 limited range in
// floating point (the driver's 8.8 fixed point differs by less than one level).
double bt601(int channel, int y, int u, int v) {
  const double c = 1.164383 * (y - 16);
  const double r[3] = {c + 1.596027 * (v - 128), c - 0.391762 * (u - 128) - 0.812968 * (v - 128),
                       c + 2.017232 * (u - 128)};
  return std::clamp(r[channel], 0.0, 255.0);
}

TEST_F(V4l2CameraTest, DeliversYuyvInColourWhenAskedOrAutomatic) {
  for (ColourCapture colour : {ColourCapture::automatic, ColourCapture::colour}) {
    auto fake = serve({.formats = {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_YUYV}});
    CameraSettings s = settings();
    s.colour = colour;
    V4l2Camera cam(fake->path(), s);
    ASSERT_EQ(cam.open(), "");
    EXPECT_NE(cam.describe().find("YUYV"), std::string::npos) << cam.describe();
    ASSERT_EQ(cam.format(), PixelFormat::rgb8);
    FramePool pool({.count = 2, .width = cam.width(), .height = cam.height(), .format = cam.format()});
    const int i = pool.borrow();
    for (int n = 0; n < 3; ++n) {
      FrameMeta& meta = pool.meta(i);
      ASSERT_EQ(cam.capture(pool.view(i), meta, 1000), CaptureStatus::frame) << cam.last_problem();
      const MutableImageView& v = pool.view(i);
      int bad = 0;
      for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x)
          for (int c = 0; c < 3; ++c) {
            const int want = static_cast<int>(
                std::lround(bt601(c, test::fake_pixel8(static_cast<std::uint32_t>(meta.sequence), x, y), 50, 200)));
            if (std::abs(v.row(y)[3 * x + c] - want) > 1 && bad++ < 3)
              ADD_FAILURE() << "frame " << meta.sequence << " (" << x << "," << y << ") channel " << c << ": "
                            << int{v.row(y)[3 * x + c]} << ", expected " << want;
          }
      EXPECT_EQ(bad, 0);
    }
    EXPECT_TRUE(pool.give_back(i));
  }
}

TEST_F(V4l2CameraTest, AutomaticColourFallsBackToGreyAndColourRefusesGrey) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
  CameraSettings s = settings();
  s.colour = ColourCapture::automatic;
  V4l2Camera automatic(fake->path(), s);
  ASSERT_EQ(automatic.open(), "");
  EXPECT_EQ(automatic.format(), PixelFormat::mono8);
  FramePool pool({.count = 2, .width = 800, .height = 600});
  expect_stream_intact(automatic, pool, 3);
  automatic.close();
  s.colour = ColourCapture::colour;
  const std::string e = V4l2Camera(fake->path(), s).open();
  EXPECT_NE(e.find("offers no colour (RGB3, BGR3, YUYV, UYVY or 8-bit Bayer) format (it offers: GREY)"),
            std::string::npos)
      << e;
}

TEST_F(V4l2CameraTest, DeliversY16AsNativeMono16) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY, V4L2_PIX_FMT_Y16}});
  V4l2Camera cam(fake->path(), settings(PixelFormat::mono16));
  ASSERT_EQ(cam.open(), "");
  EXPECT_EQ(cam.significant_bits(), 16);
  FramePool pool({.count = 2, .width = 800, .height = 600, .format = PixelFormat::mono16});
  expect_stream_intact(cam, pool, 10);
}

TEST_F(V4l2CameraTest, RefusesWhatItCannotUseSayingWhatTheDeviceOffers) {
  {
    auto fake = serve({.formats = {V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_H264}});
    V4l2Camera cam(fake->path(), settings());
    const std::string e = cam.open();
    EXPECT_NE(e.find("offers no GREY, YUYV or UYVY format (it offers: MJPG, H264)"), std::string::npos) << e;
    EXPECT_EQ(cam.state(), DeviceState::closed);
  }
  {
    auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
    const std::string e = V4l2Camera(fake->path(), settings(PixelFormat::mono16)).open();
    EXPECT_NE(e.find("no Y16, Y16 big-endian, Y12 or Y10 format (it offers: GREY)"), std::string::npos) << e;
  }
  {
    auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}, .sizes = {{640, 480}}});
    const std::string e = V4l2Camera(fake->path(), settings()).open();
    EXPECT_NE(e.find("asked for 800x600 GREY, ccdlane fake camera offers 640x480 GREY instead"), std::string::npos)
        << e;
  }
  {
    auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}, .max_fps = 30});
    const std::string e = V4l2Camera(fake->path(), settings(PixelFormat::mono8, 60)).open();
    EXPECT_NE(e.find("asked for 60 fps, ccdlane fake camera gives 30 fps"), std::string::npos) << e;
  }
  {
    const std::string e = V4l2Camera(dir_.file("absent"), settings()).open();
    EXPECT_NE(e.find("cannot open: ENOENT"), std::string::npos) << e;
    const std::string not_v4l2 = dir_.write("plain", "x");
    const std::string e2 = V4l2Camera(not_v4l2, settings()).open();
    EXPECT_NE(e2.find("not a V4L2 device (VIDIOC_QUERYCAP: ENOTTY)"), std::string::npos) << e2;
  }
}

TEST_F(V4l2CameraTest, SetsExposureGainAndNamedControls) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
  CameraSettings s = settings();
  s.exposure_us = 2000;  // 20 units of 100 us
  s.gain = 42;
  s.controls = {{"Gain", "43"}};  // by name, after the generic one
  V4l2Camera cam(fake->path(), s);
  ASSERT_EQ(cam.open(), "");
  EXPECT_EQ(fake->control(V4L2_CID_EXPOSURE_AUTO), V4L2_EXPOSURE_MANUAL);
  EXPECT_EQ(fake->control(V4L2_CID_EXPOSURE_ABSOLUTE), 20);
  EXPECT_EQ(fake->control(V4L2_CID_GAIN), 43);
  EXPECT_EQ(cam.set_control("exposure_time_absolute", "55"), "");
  EXPECT_EQ(fake->control(V4L2_CID_EXPOSURE_ABSOLUTE), 55);
  EXPECT_NE(cam.set_control("Focus", "1").find("has no control \"Focus\""), std::string::npos);
  EXPECT_NE(cam.set_control("gain", "1000").find("outside \"Gain\" range 0..100"), std::string::npos);
  EXPECT_NE(cam.set_control("gain", "lots").find("is not a number"), std::string::npos);
  EXPECT_EQ(fake->control(V4L2_CID_GAIN), 43);
}

TEST_F(V4l2CameraTest, MissingControlsAreNotedNotFatal) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}, .controls = false});
  CameraSettings s = settings();
  s.exposure_us = 2000;
  s.gain = 1;
  V4l2Camera cam(fake->path(), s);
  ASSERT_EQ(cam.open(), "");
  EXPECT_NE(cam.describe().find("no exposure control"), std::string::npos) << cam.describe();
  EXPECT_NE(cam.describe().find("no gain control"), std::string::npos) << cam.describe();
}

TEST_F(V4l2CameraTest, CountsFramesTheDeviceCouldNotDeliver) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
  V4l2Camera cam(fake->path(), settings());
  ASSERT_EQ(cam.open(), "");
  FramePool pool({.count = 1, .width = 800, .height = 600});
  FrameMeta meta;
  ASSERT_EQ(next_frame(cam, pool.view(0), meta, 2000), CaptureStatus::frame);
  const std::uint64_t before = meta.sequence;
  fake->skip_frames(3);
  ASSERT_EQ(next_frame(cam, pool.view(0), meta, 2000), CaptureStatus::frame);
  while (meta.sequence < before + 8) ASSERT_EQ(next_frame(cam, pool.view(0), meta, 2000), CaptureStatus::frame);
  EXPECT_EQ(cam.counters().dropped, 3u);
  EXPECT_TRUE(frame_is_intact(pool.view(0), meta.sequence));
}

TEST_F(V4l2CameraTest, RestartsAStalledStream) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
  CameraSettings s = settings();
  s.stall_timeout_ms = 300;
  V4l2Camera cam(fake->path(), s);
  ASSERT_EQ(cam.open(), "");
  FramePool pool({.count = 1, .width = 800, .height = 600});
  FrameMeta meta;
  ASSERT_EQ(next_frame(cam, pool.view(0), meta, 2000), CaptureStatus::frame);
  fake->stall_until_restart();
  // Frames finished before the stall may still come; then nothing, short of a stall.
  CaptureStatus quiet = CaptureStatus::frame;
  for (int i = 0; i < 10 && quiet == CaptureStatus::frame; ++i) quiet = cam.capture(pool.view(0), meta, 100);
  EXPECT_EQ(quiet, CaptureStatus::timeout);
  ASSERT_EQ(next_frame(cam, pool.view(0), meta, 3000), CaptureStatus::frame) << cam.last_problem();
  EXPECT_EQ(fake->streamon_count(), 2);
  EXPECT_EQ(cam.counters().reconnects, 1u);
  EXPECT_GE(cam.counters().timeouts, 1u);
  EXPECT_NE(cam.last_problem().find("no frame for 300 ms: stream restarted"), std::string::npos);
  EXPECT_TRUE(frame_is_intact(pool.view(0), meta.sequence));
}

TEST_F(V4l2CameraTest, ReopensAfterUnplugWhenTheDeviceReturns) {
  auto fake = serve({.formats = {V4L2_PIX_FMT_GREY}});
  CameraSettings s = settings();
  s.reopen_min_ms = 50;
  s.reopen_max_ms = 200;
  V4l2Camera cam(fake->path(), s);
  ASSERT_EQ(cam.open(), "");
  FramePool pool({.count = 1, .width = 800, .height = 600});
  FrameMeta meta;
  ASSERT_EQ(next_frame(cam, pool.view(0), meta, 2000), CaptureStatus::frame);

  std::thread unplug([&] { fake->unplug(); });
  CaptureStatus st = CaptureStatus::frame;
  for (int i = 0; i < 50 && st != CaptureStatus::recovering; ++i) st = cam.capture(pool.view(0), meta, 100);
  unplug.join();
  ASSERT_EQ(st, CaptureStatus::recovering);
  EXPECT_EQ(cam.state(), DeviceState::recovering);
  EXPECT_NE(cam.last_problem().find("device lost during VIDIOC_DQBUF: ENODEV"), std::string::npos)
      << cam.last_problem();
  EXPECT_FALSE(std::filesystem::exists(fake->path()));
  // While it is away, capture keeps trying (with backoff) and says so.
  EXPECT_EQ(cam.capture(pool.view(0), meta, 300), CaptureStatus::recovering);
  EXPECT_NE(cam.last_problem().find("cannot open: ENOENT"), std::string::npos) << cam.last_problem();

  fake->replug();
  ASSERT_EQ(next_frame(cam, pool.view(0), meta, 3000), CaptureStatus::frame) << cam.last_problem();
  EXPECT_EQ(cam.state(), DeviceState::streaming);
  EXPECT_EQ(cam.counters().reconnects, 1u);
  EXPECT_TRUE(frame_is_intact(pool.view(0), meta.sequence));
}

// A kernel video device, when the machine has one (vivid, a UVC webcam); visible skip otherwise.
TEST(V4l2RealDevice, StreamsFromTheFirstVideoNode) {
  std::string node;
  for (int i = 0; i < 64 && node.empty(); ++i)
    if (std::filesystem::exists("/dev/video" + std::to_string(i))) node = "/dev/video" + std::to_string(i);
  if (node.empty()) GTEST_SKIP() << "no /dev/video* on this machine: the real-device path is untested here";
  CameraSettings s;
  s.width = 640;
  s.height = 480;
  s.fps = 0;  // whatever the device runs at
  V4l2Camera cam(node, s);
  const std::string e = cam.open();
  if (e.find("offers no") != std::string::npos || e.find("instead") != std::string::npos)
    GTEST_SKIP() << "the first video node cannot give 640x480 mono: " << e;
  ASSERT_EQ(e, "");
  FramePool pool({.count = 1, .width = 640, .height = 480});
  FrameMeta meta;
  int frames = 0;
  for (int i = 0; i < 50 && frames < 10; ++i) frames += cam.capture(pool.view(0), meta, 500) == CaptureStatus::frame;
  EXPECT_EQ(frames, 10) << cam.describe() << ": " << cam.last_problem();
}

}  // namespace
}  // namespace ccdlane
