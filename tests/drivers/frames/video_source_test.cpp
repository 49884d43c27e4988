// A video file as the daemon's FrameSource: the file's times as recorded times, paced at
// the file's rate (checked as a lower bound on elapsed time), a size other than the
// camera's refused at open, a cut file's damage reported once, then the end; looping.
#include "drivers/frames/video_source.hpp"

#include <chrono>
#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"
#include "tests/support/test_video.hpp"

namespace ccdlane {
namespace {

using Clock = std::chrono::steady_clock;
const std::vector<std::int64_t> kTimes = {0, 40'000'000, 80'000'000, 200'000'000};

struct Capture {
  std::vector<CaptureStatus> status;
  std::vector<std::int64_t> recorded;
};

Capture capture_all(VideoSource& source, int calls) {
  const ImageBuffer frame(64, 48, PixelFormat::rgb8, 8);
  Capture c;
  FrameMeta meta;
  for (int k = 0; k < calls; ++k) {
    c.status.push_back(source.capture(frame.view(), meta, 1000));
    if (c.status.back() == CaptureStatus::frame) c.recorded.push_back(*meta.recorded_t_ns);
  }
  return c;
}

TEST(VideoSource, PlaysAtTheFilesRateWithItsTimes) {
  test::TempDir dir;
  VideoSource source({test::write_test_video(dir.file("a.mp4"), 64, 48, kTimes), false, 64, 48});
  ASSERT_EQ(source.open(), "");
  EXPECT_EQ(source.format(), PixelFormat::rgb8);
  const auto start = Clock::now();
  const Capture c = capture_all(source, 5);
  EXPECT_GE(Clock::now() - start, std::chrono::milliseconds(195));  // the last frame is due at 200 ms
  EXPECT_EQ(c.recorded, kTimes);
  EXPECT_EQ(c.status.back(), CaptureStatus::end_of_stream);
  EXPECT_EQ(source.counters().frames, 4u);
}

TEST(VideoSource, LoopsWithTimesGoingOn) {
  test::TempDir dir;
  VideoSource source({test::write_test_video(dir.file("a.mp4"), 64, 48, {0, 40'000'000}), true, 64, 48});
  ASSERT_EQ(source.open(), "");
  const Capture c = capture_all(source, 4);
  EXPECT_EQ(c.recorded, (std::vector<std::int64_t>{0, 40'000'000, 80'000'000, 120'000'000}));
}

TEST(VideoSource, AnotherSizeThanTheCameraIsRefusedAtOpen) {
  test::TempDir dir;
  const std::string path = test::write_test_video(dir.file("a.mp4"), 64, 48, kTimes);
  VideoSource source({path, false, 800, 600});
  EXPECT_EQ(source.open(), path + ": frames are 64x48, the camera is 800x600");
}

TEST(VideoSource, ACutFileReportsItsDamageOnceThenEnds) {
  test::TempDir dir;
  std::vector<std::int64_t> times;
  for (int i = 0; i < 20; ++i) times.push_back(i * 1'000'000LL);
  const std::string path = test::write_test_video(dir.file("a.mp4"), 64, 48, times);
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 300);
  VideoSource source({path, false, 64, 48});
  ASSERT_EQ(source.open(), "");
  const Capture c = capture_all(source, 25);
  EXPECT_GT(c.recorded.size(), 5u);
  EXPECT_LT(c.recorded.size(), 20u);
  EXPECT_EQ(c.status[c.recorded.size()], CaptureStatus::error);
  EXPECT_EQ(c.status.back(), CaptureStatus::end_of_stream);
  EXPECT_EQ(source.counters().errors, 1u);
  EXPECT_NE(source.last_problem().find(path + ": frame " + std::to_string(c.recorded.size())), std::string::npos)
      << source.last_problem();
}

}  // namespace
}  // namespace ccdlane
