// The video writer's contract: whole or absent (a temporary name until finish()), frames
// of its size at increasing times, a container from the file's name. (What it writes is
// read back in video_reader_test.)
#include "drivers/frames/video_writer.hpp"

#include <filesystem>
#include <stdexcept>

#include <gtest/gtest.h>

#include "base/image_buffer.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

TEST(VideoWriter, WholeOrAbsent) {
  test::TempDir dir;
  const ImageBuffer frame(64, 48, PixelFormat::mono8, 8);
  {
    VideoWriter w(dir.file("a.mp4"), {.width = 64, .height = 48});
    w.write(frame.view(), 0);
    EXPECT_TRUE(std::filesystem::exists(dir.file("a.mp4.part")));
    EXPECT_FALSE(std::filesystem::exists(dir.file("a.mp4")));
  }  // not finished: nothing left
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.mp4.part")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("a.mp4")));
  VideoWriter w(dir.file("b.mp4"), {.width = 64, .height = 48});
  w.write(frame.view(), 0);
  w.finish();
  EXPECT_TRUE(std::filesystem::exists(dir.file("b.mp4")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("b.mp4.part")));
  EXPECT_EQ(w.frames(), 1u);
}

TEST(VideoWriter, RefusesFramesOfAnotherSizeTimesThatDoNotIncreaseAndUnknownContainers) {
  test::TempDir dir;
  VideoWriter w(dir.file("a.mkv"), {.width = 64, .height = 48});
  const ImageBuffer frame(64, 48, PixelFormat::rgb8, 8), other(32, 48, PixelFormat::rgb8, 8);
  w.write(frame.view(), 40'000'000);
  EXPECT_THROW(w.write(other.view(), 80'000'000), std::runtime_error);
  EXPECT_THROW(w.write(frame.view(), 40'000'000), std::runtime_error);
  try {
    VideoWriter bad(dir.file("a.frames"), {.width = 64, .height = 48});
    ADD_FAILURE() << "an unknown container was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("a.frames") +
                                         ": no video container for this file name (use .mp4, .mkv, "
                                         ".mov or .avi)");
  }
}

}  // namespace
}  // namespace ccdlane
