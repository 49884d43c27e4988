// Frame logs on disk: written whole or not at all, read back frame for frame, other
// channels passed over, damaged events reported, and files that are no log refused.
#include "bus/frame_log.hpp"

#include <filesystem>
#include <vector>

#include <ccdlane/lane_estimate_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

const std::string kChannel = "CCDLANE_FRAMES";

struct Frames {
  Frames(int w, int h) : pixels(static_cast<std::size_t>(w * h)), view{pixels.data(), w, h, w, PixelFormat::mono8, 8} {}
  const ImageView& frame(int k) {
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i * 3 + static_cast<std::size_t>(k));
    return view;
  }
  std::vector<std::uint8_t> pixels;
  ImageView view;
};

void append_event(const std::string& path, const std::string& channel, const std::vector<std::uint8_t>& bytes) {
  lcm::LogFile log(path, "a");
  ASSERT_TRUE(log.good());
  lcm::LogEvent e;
  e.eventnum = 0;
  e.timestamp = 1;
  e.channel = channel;
  e.datalen = static_cast<std::int32_t>(bytes.size());
  e.data = const_cast<std::uint8_t*>(bytes.data());
  ASSERT_EQ(log.writeEvent(&e), 0);
}

TEST(FrameLog, WrittenFramesReadBackInOrder) {
  test::TempDir dir;
  const std::string path = dir.file("drive.lcmlog");
  Frames frames(16, 8);
  {
    FrameLogWriter w(path, kChannel);
    for (int k = 0; k < 5; ++k)
      w.write(frames.frame(k), {static_cast<std::uint64_t>(10 + k), k * 1'000'000LL, 1000 + k,
                                k % 2 ? std::optional<Gx1Angles>(Gx1Angles{0.1 * k, -0.2, 90.0}) : std::nullopt});
    EXPECT_FALSE(std::filesystem::exists(path)) << "not in place before finish()";
    w.finish();
    EXPECT_EQ(w.frames_written(), 5u);
  }
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));

  FrameLogReader r(path, kChannel);
  for (int k = 0; k < 5; ++k) {
    ASSERT_EQ(r.next(), FrameLogReader::Next::frame) << r.problem();
    EXPECT_EQ(r.record().sequence, static_cast<std::uint64_t>(10 + k));
    EXPECT_EQ(r.record().t_ns, k * 1'000'000LL);
    EXPECT_EQ(r.record().utime, 1000 + k);
    EXPECT_EQ(r.record().gyro.has_value(), k % 2 == 1);
    const ImageView& expected = frames.frame(k);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) ASSERT_EQ(r.image().at(x, y), expected.at(x, y));
  }
  EXPECT_EQ(r.next(), FrameLogReader::Next::end);
  EXPECT_EQ(r.frames(), 5u);
}

TEST(FrameLog, AnUnfinishedLogLeavesNothingBehind) {
  test::TempDir dir;
  const std::string path = dir.file("cut.lcmlog");
  Frames frames(4, 4);
  {
    FrameLogWriter w(path, kChannel);
    w.write(frames.frame(0), {0, 0, 0, std::nullopt});
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
}

TEST(FrameLog, AnExistingFileIsNeverOverwritten) {
  test::TempDir dir;
  const std::string path = dir.write("taken.lcmlog", "precious");
  try {
    FrameLogWriter w(path, kChannel);
    FAIL() << "no error";
  } catch (const FrameLogError& e) {
    EXPECT_EQ(std::string(e.what()), path + ": already exists; choose another name");
  }
  EXPECT_EQ(test::run_process({"/bin/cat", path}).out, "precious");
}

TEST(FrameLog, OtherChannelsArePassedOverAndDamagedFramesReported) {
  test::TempDir dir;
  const std::string path = dir.file("mixed.lcmlog");
  Frames frames(4, 2);
  {
    FrameLogWriter w(path, kChannel);
    w.write(frames.frame(0), {0, 0, 0, std::nullopt});
    w.finish();
  }
  lane_estimate_t lane{};
  std::vector<std::uint8_t> lane_bytes(static_cast<std::size_t>(lane.getEncodedSize()));
  lane.encode(lane_bytes.data(), 0, static_cast<int>(lane_bytes.size()));
  append_event(path, "CCDLANE_LANES", lane_bytes);  // another channel: passed over
  append_event(path, kChannel, lane_bytes);         // the wrong type on the frames channel
  frame_t bad{};
  prepare_frame_message(bad, 4, 2, PixelFormat::mono8);
  bad.sequence = 9;
  bad.significant_bits = 8;
  bad.width = 5;  // 5 x 2 pixels do not fit in data_size 8 with row_stride 4
  std::vector<std::uint8_t> bad_bytes(static_cast<std::size_t>(bad.getEncodedSize()));
  bad.encode(bad_bytes.data(), 0, static_cast<int>(bad_bytes.size()));
  append_event(path, kChannel, bad_bytes);
  // A last good frame: reading goes on after damage.
  frame_t good{};
  prepare_frame_message(good, 4, 2, PixelFormat::mono8);
  ASSERT_TRUE(to_frame_message(frames.frame(1), {1, 1, 1, std::nullopt}, good));
  std::vector<std::uint8_t> good_bytes(static_cast<std::size_t>(good.getEncodedSize()));
  good.encode(good_bytes.data(), 0, static_cast<int>(good_bytes.size()));
  append_event(path, kChannel, good_bytes);

  FrameLogReader r(path, kChannel);
  ASSERT_EQ(r.next(), FrameLogReader::Next::frame);
  EXPECT_EQ(r.record().sequence, 0u);
  ASSERT_EQ(r.next(), FrameLogReader::Next::damaged);
  EXPECT_NE(r.problem().find(": event 2 on CCDLANE_FRAMES: not a ccdlane.frame_t message"), std::string::npos)
      << r.problem();
  ASSERT_EQ(r.next(), FrameLogReader::Next::damaged);
  EXPECT_NE(r.problem().find("frame 9: row_stride 4 is shorter than a row"), std::string::npos) << r.problem();
  EXPECT_EQ(r.record().sequence, 9u);
  ASSERT_EQ(r.next(), FrameLogReader::Next::frame) << r.problem();
  EXPECT_EQ(r.record().sequence, 1u);
  EXPECT_EQ(r.next(), FrameLogReader::Next::end);
  EXPECT_EQ(r.other_events(), 1u);
  EXPECT_EQ(r.frames(), 4u);
}

TEST(FrameLog, AFileThatIsNoLogIsRefusedWithTheReason) {
  test::TempDir dir;
  const std::string text = dir.write("frames.csv", "file,t_ns\n");
  EXPECT_THROW(FrameLogReader(text, kChannel), FrameLogError);
  try {
    FrameLogReader r(text, kChannel);
  } catch (const FrameLogError& e) {
    EXPECT_EQ(std::string(e.what()), text + ": not an LCM log (no LCM event at its start)");
  }
  try {
    FrameLogReader r(dir.file("absent.lcmlog"), kChannel);
  } catch (const FrameLogError& e) {
    EXPECT_EQ(std::string(e.what()), dir.file("absent.lcmlog") + ": No such file or directory");
  }
}

}  // namespace
}  // namespace ccdlane
