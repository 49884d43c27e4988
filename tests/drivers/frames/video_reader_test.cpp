// Video files read back: every container and codec ccdlane takes, frame times from the
// container (variable rates included), the committed real drive, and each kind of bad
// file named in one line (cut short, damaged, not a video, unsupported codec).
#include "drivers/frames/video_reader.hpp"

#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "base/image_buffer.hpp"
#include "tests/support/run_process.hpp"
#include "tests/support/test_video.hpp"

namespace ccdlane {
namespace {

const std::string kSegA = std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-drives/project_video_segA.mp4";

// Times 40 ms apart but for one long gap: a variable frame rate.
const std::vector<std::int64_t> kVfrTimes = {0, 40'000'000, 80'000'000, 200'000'000, 240'000'000, 280'000'000};

struct Decoded {
  std::vector<std::int64_t> t_ns;
  std::vector<int> max_error;  // against the frame painted
  std::vector<double> mean_error;
  VideoRead last = VideoRead::frame;
};

Decoded read_all(VideoReader& r) {
  Decoded d;
  const ImageBuffer got(r.width(), r.height(), r.format(), 8);
  const ImageBuffer want(r.width(), r.height(), r.format(), 8);
  std::int64_t t = 0;
  while ((d.last = r.next(got.view(), t)) == VideoRead::frame) {
    test::paint_test_frame(want.view(), static_cast<int>(d.t_ns.size()));
    d.t_ns.push_back(t);
    d.max_error.push_back(test::max_abs_difference(got.view(), want.view()));
    d.mean_error.push_back(test::mean_abs_difference(got.view(), want.view()));
  }
  return d;
}

TEST(VideoPath, ToldByExtension) {
  EXPECT_TRUE(is_video_path("drive.mp4"));
  EXPECT_TRUE(is_video_path("/a/b/DRIVE.MKV"));
  EXPECT_TRUE(is_video_path("x.mov"));
  EXPECT_TRUE(is_video_path("x.avi"));
  EXPECT_FALSE(is_video_path("drive.lcmlog"));
  EXPECT_FALSE(is_video_path("dir.mp4/frames"));
  EXPECT_FALSE(is_video_path("mp4"));
}

TEST(VideoReader, LosslessH264InMp4KeepsPixelsAndVariableTimes) {
  test::TempDir tmp;
  VideoWriterOptions o;
  o.lossless = true;
  VideoReader r(test::write_test_video(tmp.file("a.mp4"), 64, 48, kVfrTimes, o));
  EXPECT_EQ(r.width(), 64);
  EXPECT_EQ(r.height(), 48);
  EXPECT_EQ(r.format(), PixelFormat::rgb8);
  EXPECT_EQ(r.codec(), "h264");
  const Decoded d = read_all(r);
  EXPECT_EQ(d.last, VideoRead::end) << r.problem();
  EXPECT_EQ(d.t_ns, kVfrTimes);
  // RGB -> limited-range YUV -> RGB rounds; chroma is shared by 2x2 pixels.
  for (const int e : d.max_error) EXPECT_LE(e, 12);
  EXPECT_EQ(r.non_monotonic(), 0u);
}

struct Case {
  const char* file;
  const char* encoder;
  const char* codec;
  int tb_den;         // AVI keeps one tick per frame
  double mean_error;  // lossy: the test pattern's sharp wrap costs most
};

TEST(VideoReader, EveryContainerAndCodec) {
  const Case cases[] = {{"c.avi", "mjpeg", "mjpeg", 25, 8.0},
                        {"d.mov", "libx264", "h264", 90'000, 8.0},
                        {"e.mkv", "mjpeg", "mjpeg", 90'000, 8.0}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    test::TempDir tmp;
    VideoWriterOptions o;
    o.encoder = c.encoder;
    o.time_base_den = c.tb_den;
    const std::vector<std::int64_t> times = {0, 40'000'000, 80'000'000, 120'000'000};
    VideoReader r(test::write_test_video(tmp.file(c.file), 64, 48, times, o));
    EXPECT_EQ(r.codec(), c.codec);
    const Decoded d = read_all(r);
    EXPECT_EQ(d.last, VideoRead::end);
    EXPECT_EQ(d.t_ns, times);
    for (const double e : d.mean_error) EXPECT_LE(e, c.mean_error);
  }
}

// H.265 from a file written once (tests/data/README.md): libx265's encoder leaks at open.
TEST(VideoReader, H265InMatroska) {
  VideoReader r(std::string(CCDLANE_TEST_DATA_DIR) + "/video/pattern-hevc.mkv");
  EXPECT_EQ(r.codec(), "hevc");
  const Decoded d = read_all(r);
  EXPECT_EQ(d.last, VideoRead::end) << r.problem();
  EXPECT_EQ(d.t_ns, (std::vector<std::int64_t>{0, 40'000'000, 80'000'000, 120'000'000}));
  for (const double e : d.mean_error) EXPECT_LE(e, 8.0);
}

TEST(VideoReader, RewindStartsOver) {
  test::TempDir tmp;
  VideoReader r(test::write_test_video(tmp.file("a.mp4"), 64, 48, kVfrTimes));
  const Decoded first = read_all(r);
  ASSERT_TRUE(r.rewind());
  const Decoded second = read_all(r);
  EXPECT_EQ(second.t_ns, first.t_ns);
  EXPECT_EQ(second.last, VideoRead::end) << r.problem();
}

TEST(VideoReader, RealDriveFromMp4) {
  VideoReader r(kSegA);
  EXPECT_EQ(r.width(), 1280);
  EXPECT_EQ(r.height(), 720);
  EXPECT_EQ(r.codec(), "h264");
  EXPECT_DOUBLE_EQ(r.frame_rate_hz(), 25.0);
  const ImageBuffer frame(1280, 720, PixelFormat::rgb8, 8);
  std::int64_t t = 0;
  std::uint64_t n = 0;
  VideoRead got;
  while ((got = r.next(frame.view(), t)) == VideoRead::frame) {
    EXPECT_EQ(t, static_cast<std::int64_t>(n) * 40'000'000);
    ++n;
  }
  EXPECT_EQ(got, VideoRead::end) << r.problem();
  EXPECT_EQ(n, 211u);
  // A road picture in colour: the sky above is bluer than it is red.
  const std::uint8_t* sky = frame.view().row(50) + 3 * 640;
  EXPECT_GT(int{sky[2]}, int{sky[0]});
}

TEST(VideoReader, CutShortKeepsTheFramesBeforeTheCutAndNamesIt) {
  test::TempDir tmp;
  const std::string cut = tmp.file("cut.mp4");
  std::filesystem::copy_file(kSegA, cut);
  std::filesystem::resize_file(cut, 3'000'000);  // of 10.8 MB
  VideoReader r(cut);
  const ImageBuffer frame(1280, 720, PixelFormat::rgb8, 8);
  std::int64_t t = 0;
  VideoRead got;
  while ((got = r.next(frame.view(), t)) == VideoRead::frame) {
  }
  EXPECT_EQ(got, VideoRead::damaged);
  EXPECT_GT(r.frames_read(), 10u);
  EXPECT_LT(r.frames_read(), 211u);
  const std::string problem(r.problem());
  EXPECT_NE(problem.find(cut + ": frame " + std::to_string(r.frames_read())), std::string::npos) << problem;
  EXPECT_NE(problem.find("cut short"), std::string::npos) << problem;
  EXPECT_EQ(r.next(frame.view(), t), VideoRead::damaged);  // stays stopped
}

TEST(VideoReader, DamagedDataStopsAtTheDamagedFrame) {
  test::TempDir tmp;
  std::vector<std::int64_t> times;
  for (int i = 0; i < 30; ++i) times.push_back(i * 40'000'000LL);
  VideoWriterOptions o;
  o.encoder = "mjpeg";
  const std::string path = test::write_test_video(tmp.file("d.mkv"), 64, 48, times, o);
  {  // garbage over the middle of the file: some frame's JPEG data
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(std::filesystem::file_size(path) / 2));
    const std::string garbage(200, '\xA5');
    f.write(garbage.data(), static_cast<std::streamsize>(garbage.size()));
  }
  VideoReader r(path);
  const Decoded d = read_all(r);
  EXPECT_EQ(d.last, VideoRead::damaged);
  EXPECT_GT(d.t_ns.size(), 5u);
  EXPECT_LT(d.t_ns.size(), 30u);
  EXPECT_NE(std::string(r.problem()).find(": frame "), std::string::npos) << r.problem();
}

// A frame whose time does not come after the one before is skipped, counted and named.
TEST(VideoReader, ATimeThatDoesNotIncreaseIsSkippedCountedAndNamed) {
  VideoReader r(std::string(CCDLANE_TEST_DATA_DIR) + "/video/repeated-time-mjpeg.mkv");
  const ImageBuffer frame(64, 48, r.format(), 8);
  std::vector<std::int64_t> times;
  std::vector<std::uint64_t> index;
  std::int64_t t = 0;
  while (r.next(frame.view(), t) == VideoRead::frame) times.push_back(t), index.push_back(r.frame_index());
  EXPECT_EQ(times, (std::vector<std::int64_t>{0, 40'000'000, 80'000'000, 160'000'000, 200'000'000}));
  EXPECT_EQ(index, (std::vector<std::uint64_t>{0, 1, 2, 4, 5}));
  EXPECT_EQ(r.non_monotonic(), 1u);
  EXPECT_EQ(r.first_non_monotonic(), 3);
}

TEST(VideoReader, RefusesWhatIsNotAReadableVideo) {
  test::TempDir tmp;
  const auto error_of = [](const std::string& path) {
    try {
      VideoReader r(path);
    } catch (const VideoError& e) {
      return std::string(e.what());
    }
    return std::string("(opened)");
  };
  const std::string text = tmp.write("notes.mp4", "frame,t_ns\nthis is not a video\n");
  EXPECT_EQ(error_of(text).rfind(text + ": not a video", 0), 0u) << error_of(text);
  EXPECT_EQ(error_of(tmp.file("missing.mp4")), tmp.file("missing.mp4") + ": no such file");
  VideoWriterOptions o;
  o.encoder = "ffv1";
  const std::string ffv1 = test::write_test_video(tmp.file("f.mkv"), 64, 48, {0, 40'000'000}, o);
  EXPECT_EQ(error_of(ffv1), ffv1 + ": unsupported codec ffv1 (ccdlane reads H.264, H.265 and MJPEG)");
  // An MP4 cut before its index holds nothing to keep.
  const std::string cut = tmp.file("cut.mp4");
  std::filesystem::copy_file(kSegA, cut);
  std::filesystem::resize_file(cut, 1000);
  EXPECT_EQ(error_of(cut).rfind(cut + ": not a video, or cut short before its index", 0), 0u) << error_of(cut);
}

}  // namespace
}  // namespace ccdlane
