// A frame directory as the daemon's FrameSource: order, gyro, damaged frames, looping,
// end of stream, timeouts, and pacing (checked as lower bounds on elapsed time, which a
// slow machine cannot break).
#include "drivers/frames/frame_directory_source.hpp"

#include <time.h>

#include <filesystem>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/frames/frame_directory_writer.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

std::int64_t now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

struct Recording {
  test::TempDir tmp;
  std::string path = tmp.file("rec");
  // n frames of 16x8 whose pixels hold their index, t_ns = i * step_ns, gyro roll = i.
  Recording(int n, std::int64_t step_ns) {
    std::vector<std::uint8_t> px(16 * 8);
    FrameDirectoryWriter w(path, {true, {}});
    for (int i = 0; i < n; ++i) {
      std::fill(px.begin(), px.end(), static_cast<std::uint8_t>(i));
      w.write(ImageView{px.data(), 16, 8, 16, PixelFormat::mono8, 8}, i * step_ns, Gx1Angles{double(i), 0.5, 0.0});
    }
    w.finish();
  }
};

struct Frame16x8 {
  std::vector<std::uint8_t> px = std::vector<std::uint8_t>(16 * 8, 0xFF);
  MutableImageView view{px.data(), 16, 8, 16, PixelFormat::mono8, 8};
};

TEST(FrameDirectorySource, DeliversEveryFrameThenEndsAndReportsDamage) {
  Recording rec(4, 1'000'000);
  std::filesystem::remove(rec.path + "/000002.pgm");
  FrameDirectorySource src({rec.path, 10'000.0, false, 16, 8});
  ASSERT_EQ(src.open(), "");
  EXPECT_EQ(src.width(), 16);
  EXPECT_EQ(src.format(), PixelFormat::mono8);
  Frame16x8 b;
  FrameMeta meta;
  std::vector<CaptureStatus> st;
  std::vector<std::uint64_t> seq;
  for (int k = 0; k < 5; ++k) {
    st.push_back(src.capture(b.view, meta, 1000));
    if (st.back() == CaptureStatus::frame) {
      seq.push_back(meta.sequence);
      EXPECT_EQ(b.px[0], meta.sequence);
      ASSERT_TRUE(meta.gyro);
      EXPECT_EQ(meta.gyro->roll_deg, double(meta.sequence));
      EXPECT_EQ(meta.gyro->pitch_deg, 0.5);
      // Played at 10 kHz, recorded 1 ms apart: each frame keeps its recorded time.
      EXPECT_EQ(meta.recorded_t_ns, static_cast<std::int64_t>(meta.sequence) * 1'000'000);
      EXPECT_EQ(meta.frame_t_ns(), *meta.recorded_t_ns);
    }
  }
  EXPECT_EQ(st, (std::vector<CaptureStatus>{CaptureStatus::frame, CaptureStatus::frame, CaptureStatus::error,
                                            CaptureStatus::frame, CaptureStatus::end_of_stream}));
  EXPECT_EQ(seq, (std::vector<std::uint64_t>{0, 1, 3}));
  EXPECT_EQ(src.last_problem(), rec.path + "/000002.pgm: missing (no such file)");
  EXPECT_EQ(src.counters().frames, 3u);
  EXPECT_EQ(src.counters().errors, 1u);
  EXPECT_NE(src.describe().find("frames:" + rec.path + " 16x8 mono8"), std::string::npos) << src.describe();
}

// What the writer records of the vehicle (speed, indicator; an unknown speed as an empty
// cell) the source gives back with each frame, so a recording replays with its inputs.
TEST(FrameDirectorySource, GivesBackTheVehicleColumnsTheWriterRecorded) {
  test::TempDir tmp;
  const std::string path = tmp.file("rec");
  const std::vector<FrameVehicle> written = {{72.5, TurnIndicator::none},
                                             {80.25, TurnIndicator::left},
                                             {std::nullopt, TurnIndicator::right},
                                             {0.0, TurnIndicator::both}};
  {
    std::vector<std::uint8_t> px(16 * 8, 9);
    FrameDirectoryWriter w(path, {false, {}, true});
    for (std::size_t i = 0; i < written.size(); ++i)
      w.write(ImageView{px.data(), 16, 8, 16, PixelFormat::mono8, 8}, static_cast<std::int64_t>(i) * 1'000'000,
              std::nullopt, {}, written[i]);
    w.finish();
  }
  FrameDirectorySource src({path, 10'000.0, false, 16, 8});
  ASSERT_EQ(src.open(), "");
  Frame16x8 b;
  for (const FrameVehicle& v : written) {
    FrameMeta meta;
    ASSERT_EQ(src.capture(b.view, meta, 1000), CaptureStatus::frame);
    EXPECT_EQ(meta.speed_kmh, v.speed_kmh) << "frame " << meta.sequence;
    EXPECT_EQ(meta.indicator, v.indicator) << "frame " << meta.sequence;
  }
}

TEST(FrameDirectorySource, ARecordingWithoutVehicleColumnsGivesNoVehicleValues) {
  Recording rec(2, 1'000'000);
  FrameDirectorySource src({rec.path, 10'000.0, false, 16, 8});
  ASSERT_EQ(src.open(), "");
  Frame16x8 b;
  FrameMeta meta;
  ASSERT_EQ(src.capture(b.view, meta, 1000), CaptureStatus::frame);
  EXPECT_FALSE(meta.speed_kmh);
  EXPECT_FALSE(meta.indicator) << "the live bus's indicator, not a recorded none, applies";
}

TEST(FrameDirectorySource, LoopsWithIncreasingSequenceNumbersAndFrameTimes) {
  Recording rec(3, 1'000'000);
  FrameDirectorySource src({rec.path, 10'000.0, true, 0, 0});
  ASSERT_EQ(src.open(), "");
  Frame16x8 b;
  FrameMeta meta;
  std::int64_t last_t = 0;
  for (std::uint64_t k = 0; k < 8; ++k) {
    ASSERT_EQ(src.capture(b.view, meta, 1000), CaptureStatus::frame);
    EXPECT_EQ(meta.sequence, k);
    EXPECT_EQ(b.px[0], k % 3);
    EXPECT_GE(meta.t_ns, last_t);
    last_t = meta.t_ns;
    // 0, 1, 2 ms as recorded; each later pass one recording (3 ms: 2 ms + one period) on.
    EXPECT_EQ(meta.recorded_t_ns, static_cast<std::int64_t>(k) * 1'000'000) << "frame " << k;
  }
}

TEST(FrameDirectorySource, PacesAtTheRecordedTimesOrTheGivenRate) {
  Recording rec(5, 10'000'000);  // 10 ms apart
  Frame16x8 b;
  FrameMeta meta;
  for (double rate : {0.0, 50.0}) {  // as recorded: 4 gaps of 10 ms; 50 Hz: 4 gaps of 20 ms
    FrameDirectorySource src({rec.path, rate, false, 16, 8});
    ASSERT_EQ(src.open(), "");
    const std::int64_t t0 = now_ns();
    for (int k = 0; k < 5; ++k) ASSERT_EQ(src.capture(b.view, meta, 1000), CaptureStatus::frame);
    EXPECT_GE(now_ns() - t0, rate > 0 ? 80'000'000 : 40'000'000) << "rate " << rate;
  }
}

// A folder of pictures without frames.csv (a camera's snapshots) plays in name order at
// 25 Hz, and says so.
TEST(FrameDirectorySource, PlaysAFolderOfPicturesInNameOrderAt25Hz) {
  Recording rec(3, 1'000'000);
  std::filesystem::remove(rec.path + "/frames.csv");
  FrameDirectorySource src({rec.path, 0.0, false, 16, 8});
  ASSERT_EQ(src.open(), "");
  EXPECT_NE(src.describe().find("in name order at 25 Hz"), std::string::npos) << src.describe();
  Frame16x8 b;
  FrameMeta meta;
  const std::int64_t t0 = now_ns();
  for (int k = 0; k < 3; ++k) {
    ASSERT_EQ(src.capture(b.view, meta, 1000), CaptureStatus::frame);
    EXPECT_EQ(b.px[0], k) << "the pictures' names, 000000.pgm .. 000002.pgm, are their order";
    EXPECT_EQ(meta.recorded_t_ns, k * 40'000'000);
  }
  EXPECT_GE(now_ns() - t0, 80'000'000);
}

TEST(FrameDirectorySource, TimesOutWhenTheNextFrameIsNotDueYet) {
  Recording rec(2, 5'000'000'000);  // the second frame 5 s after the first
  FrameDirectorySource src({rec.path, 0.0, false, 16, 8});
  ASSERT_EQ(src.open(), "");
  Frame16x8 b;
  FrameMeta meta;
  ASSERT_EQ(src.capture(b.view, meta, 20), CaptureStatus::frame);
  const std::int64_t t0 = now_ns();
  EXPECT_EQ(src.capture(b.view, meta, 20), CaptureStatus::timeout);
  EXPECT_GE(now_ns() - t0, 20'000'000);
  EXPECT_EQ(src.counters().timeouts, 1u);
}

TEST(FrameDirectorySource, OpenNamesWhatIsWrong) {
  Recording rec(1, 0);
  FrameDirectorySource wrong({rec.path, 0.0, false, 800, 600});
  EXPECT_EQ(wrong.open(), rec.path + ": frames are 16x8, the camera is 800x600");
  FrameDirectorySource none({rec.tmp.file("nothing"), 0.0, false, 0, 0});
  EXPECT_NE(none.open().find("nothing/frames.csv: cannot read"), std::string::npos);
  std::filesystem::remove(rec.path + "/000000.pgm");
  FrameDirectorySource unreadable({rec.path, 0.0, false, 0, 0});
  EXPECT_EQ(unreadable.open(),
            rec.path + ": none of the 1 frames can be read (" + rec.path + "/000000.pgm: missing (no such file))");
}

TEST(FrameDirectorySource, CaptureAllocatesNothing) {
  Recording rec(3, 1'000);
  std::filesystem::remove(rec.path + "/000001.pgm");
  FrameDirectorySource src({rec.path, 100'000.0, true, 16, 8});
  ASSERT_EQ(src.open(), "");
  Frame16x8 b;
  FrameMeta meta;
  int frames = 0, errors = 0;
  test::AllocationScope scope;
  for (int k = 0; k < 9; ++k) {
    const CaptureStatus s = src.capture(b.view, meta, 1000);
    frames += s == CaptureStatus::frame;
    errors += s == CaptureStatus::error;
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(frames, 6);
  EXPECT_EQ(errors, 3);
}

}  // namespace
}  // namespace ccdlane
