// The V4L2 capture path allocates nothing: steady streaming, a stall restart and a whole
// unplug/reopen cycle, counted on the capturing thread (the fake device's own threads
// allocate freely and are not counted).
#include <linux/videodev2.h>

#include <cstdlib>
#include <thread>

#include <gtest/gtest.h>

#include "drivers/camera/frame_pool.hpp"
#include "drivers/camera/v4l2_camera.hpp"
#include "tests/drivers/camera/fake_v4l2/fake_v4l2_device.hpp"
#include "tests/drivers/camera/malloc_counter.hpp"
#include "tests/drivers/camera/private_namespace.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string g_namespace_problem = test::enter_private_mount_namespace();

struct CountedCapture {
  V4l2Camera& cam;
  std::uint64_t mallocs = 0;
  CaptureStatus operator()(const MutableImageView& into, FrameMeta& meta, int timeout_ms) {
    const std::uint64_t before = test::mallocs_in_this_thread();
    const CaptureStatus s = cam.capture(into, meta, timeout_ms);
    mallocs += test::mallocs_in_this_thread() - before;
    return s;
  }
  CaptureStatus until_frame(const MutableImageView& into, FrameMeta& meta, int attempts) {
    CaptureStatus s = CaptureStatus::timeout;
    for (int i = 0; i < attempts && s != CaptureStatus::frame; ++i) s = (*this)(into, meta, 200);
    return s;
  }
};

TEST(V4l2CameraNoAlloc, CapturePathIncludingRecoveryNeverAllocates) {
  if (!g_namespace_problem.empty()) GTEST_SKIP() << g_namespace_problem;
  if (!test::malloc_counting_available()) GTEST_SKIP() << "malloc is owned by the sanitizer in this build";
  test::TempDir dir;
  test::FakeV4l2Device fake(dir.file("video0"), {.formats = {V4L2_PIX_FMT_YUYV}});
  CameraSettings s;
  s.fps = 120;
  s.stall_timeout_ms = 200;
  s.reopen_min_ms = 20;
  s.reopen_max_ms = 100;
  V4l2Camera cam(fake.path(), s);
  ASSERT_EQ(cam.open(), "");
  FramePool pool({.count = 3, .width = 800, .height = 600});
  CountedCapture capture{cam};

  // The counter does count on this thread (else a zero below would prove nothing).
  const std::uint64_t probe = test::mallocs_in_this_thread();
  void* (*volatile allocate)(std::size_t) = std::malloc;  // volatile: not elided
  std::free(allocate(16));
  ASSERT_GT(test::mallocs_in_this_thread(), probe);

  for (int n = 0; n < 60; ++n) {
    const int i = pool.borrow();
    ASSERT_EQ(capture(pool.view(i), pool.meta(i), 1000), CaptureStatus::frame) << cam.last_problem();
    ASSERT_TRUE(pool.give_back(i));
  }
  // The frames the device filled before it stalled come first (at 120 fps a few may be
  // queued): the restart happens once they are taken and the stall timeout has passed.
  fake.stall_until_restart();
  FrameMeta meta;
  const std::uint64_t reconnects_before_stall = cam.counters().reconnects;
  for (int i = 0; i < 20 && cam.counters().reconnects == reconnects_before_stall; ++i) capture(pool.view(0), meta, 200);
  ASSERT_GT(cam.counters().reconnects, reconnects_before_stall) << "the stalled stream was restarted";
  ASSERT_EQ(capture.until_frame(pool.view(0), meta, 20), CaptureStatus::frame);
  std::thread unplug([&] { fake.unplug(); });
  while (capture(pool.view(0), meta, 100) != CaptureStatus::recovering) {
  }
  unplug.join();
  EXPECT_EQ(capture(pool.view(0), meta, 100), CaptureStatus::recovering);
  fake.replug();
  ASSERT_EQ(capture.until_frame(pool.view(0), meta, 20), CaptureStatus::frame) << cam.last_problem();
  // The stall restart and the reopen, at least: a machine loaded enough to hold the fake
  // device's thread past the 200 ms stall timeout adds a restart of its own, and that
  // path must not allocate either. (Without waiting for the restart above, the frames
  // queued before the stall made it 1 now and then: the stall was never noticed.)
  EXPECT_GE(cam.counters().reconnects, 2u);
  EXPECT_EQ(capture.mallocs, 0u);
}

}  // namespace
}  // namespace ccdlane
