// `ccdlane grab` as a user runs it: from the GigE Vision simulator (private network
// namespace) and from the FUSE fake V4L2 camera (private mount namespace), recording
// frame directories that the frame-directory reader then reads back whole.
#include <linux/videodev2.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "drivers/frames/frame_directory.hpp"
#include "tests/drivers/camera/fake_v4l2/fake_v4l2_device.hpp"
#include "tests/drivers/camera/private_namespace.hpp"
#include "tests/support/run_process.hpp"

extern char** environ;

namespace ccdlane {
namespace {

const std::string g_namespace_problem = [] {
  std::string e = test::enter_private_network_namespace();
  return e.empty() ? test::enter_private_mount_namespace() : e;
}();

// Reads every frame of the directory back; returns how many decode.
int readable_frames(const std::string& dir, int width, int height) {
  FrameDirectory frames(dir);
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width * height));
  const MutableImageView into{pixels.data(), width, height, width, PixelFormat::mono8, 8};
  int ok = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) ok += frames.read(i, into) == PgmFault::none;
  EXPECT_TRUE(frames.issues().empty());
  return ok;
}

class GrabCommandTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!g_namespace_problem.empty()) GTEST_SKIP() << g_namespace_problem;
  }
  test::TempDir dir_;
};

TEST_F(GrabCommandTest, GrabsAHundredFramesFromTheGigEVisionSimulator) {
  char prog[] = "arv-fake-gv-camera-0.8", opt[] = "-i", addr[] = "127.0.0.1";
  char* argv[] = {prog, opt, addr, nullptr};
  pid_t sim = -1;
  ASSERT_EQ(posix_spawnp(&sim, prog, nullptr, nullptr, argv, environ), 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const std::string out = dir_.file("rec");
  const auto r = test::run_process({CCDLANE_TOOL, "grab", "aravis:127.0.0.1", "--count", "100", "--out", out});
  kill(sim, SIGKILL);
  waitpid(sim, nullptr, 0);
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.out.find("device: aravis:127.0.0.1 (Aravis Fake"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("format: 800x600 mono8"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames: 100 received, 0 dropped"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rate: "), std::string::npos);
  EXPECT_NE(r.out.find("latency (frame timestamp to delivery): p50 "), std::string::npos);
  EXPECT_EQ(readable_frames(out, 800, 600), 100);
}

TEST_F(GrabCommandTest, GrabsFromAV4l2NodeReducingYuyv) {
  if (access("/dev/fuse", R_OK | W_OK) != 0) GTEST_SKIP() << "no usable /dev/fuse";
  test::FakeV4l2Device fake(dir_.file("video0"), {.formats = {V4L2_PIX_FMT_YUYV}, .sizes = {{640, 480}}});
  const std::string out = dir_.file("rec");
  const auto r = test::run_process({CCDLANE_TOOL, "grab", "v4l2:" + fake.path(), "--count", "20", "--width", "640",
                                    "--height", "480", "--fps", "50", "--out", out});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.out.find("640x480 YUYV 50 fps"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames: 20 received"), std::string::npos) << r.out;
  EXPECT_EQ(readable_frames(out, 640, 480), 20);
}

TEST_F(GrabCommandTest, ExplainsBadSourcesAndUnopenableCameras) {
  auto r = test::run_process({CCDLANE_TOOL, "grab", "webcam0"});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane: source \"webcam0\": expected v4l2:/dev/videoN or aravis:ID\n");
  r = test::run_process({CCDLANE_TOOL, "grab", "v4l2:"});
  EXPECT_EQ(r.exit_status, 2);
  r = test::run_process({CCDLANE_TOOL, "grab", "v4l2:" + dir_.file("video9"), "--out", dir_.file("rec")});
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_NE(r.err.find("cannot open: ENOENT"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.file("rec")));  // nothing left behind
  r = test::run_process({CCDLANE_TOOL, "grab", "aravis:Fake_1", "--format", "mono12"});
  EXPECT_EQ(r.exit_status, 2);
}

}  // namespace
}  // namespace ccdlane
