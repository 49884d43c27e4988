// Frame logs on disk: written whole or not at all, read back frame for frame, other
// channels passed over, damaged events reported, and files that are no log refused.
#include "bus/frame_log.hpp"

#include <filesystem>
#include <fstream>
#include <functional>
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
    for (std::size_t i = 0; i < pixels.size(); ++i)
      pixels[i] = static_cast<std::uint8_t>(i * 3 + static_cast<std::size_t>(k));
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

// A log of six 16x8 frames (sequences 0..5), every event the same size, and what a
// reader makes of it after `damage` changed the bytes of event 3.
struct DamagedLog {
  static constexpr int kFrames = 6;
  test::TempDir dir;
  std::string path = dir.file("damaged.lcmlog");
  std::vector<char> bytes;
  std::size_t event_bytes = 0;

  DamagedLog() {
    Frames frames(16, 8);
    {
      FrameLogWriter w(path, kChannel);
      for (int k = 0; k < kFrames; ++k)
        w.write(frames.frame(k), {static_cast<std::uint64_t>(k), k * 1000LL, 5000 + k, std::nullopt});
      w.finish();
    }
    std::ifstream in(path, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    event_bytes = bytes.size() / kFrames;
  }
  std::size_t at(int event, std::size_t field) const { return static_cast<std::size_t>(event) * event_bytes + field; }
  void put_be32(std::size_t offset, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes[offset + static_cast<std::size_t>(i)] = static_cast<char>(v >> (24 - 8 * i));
  }
  void put_be64(std::size_t offset, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes[offset + static_cast<std::size_t>(i)] = static_cast<char>(v >> (56 - 8 * i));
  }
  void save() {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }

  struct Outcome {
    std::vector<std::uint64_t> sequences;  // of the frames read whole
    std::size_t damaged = 0, lost_reports = 0;
    std::uint64_t lost_events = 0;
    bool truncated = false;
    std::string problems;
  };
  Outcome read() {
    save();
    Outcome o;
    FrameLogReader r(path, kChannel);
    for (FrameLogReader::Next n; (n = r.next()) != FrameLogReader::Next::end;) {
      if (n == FrameLogReader::Next::frame) o.sequences.push_back(r.record().sequence);
      if (n == FrameLogReader::Next::damaged) ++o.damaged;
      if (n == FrameLogReader::Next::lost) ++o.lost_reports;
      if (n != FrameLogReader::Next::frame) o.problems += r.problem() + "\n";
    }
    o.lost_events = r.lost_events();
    o.truncated = r.truncated();
    return o;
  }
};

// Header field offsets within an event (lcm/eventlog.c).
constexpr std::size_t kSyncField = 0, kEventnumField = 4, kTimestampField = 12, kChannelLengthField = 20,
                      kDataLengthField = 24, kChannelField = 28;

struct Damage {
  const char* what;
  std::function<void(DamagedLog&)> apply;
};

TEST(FrameLog, DamageAtEveryHeaderFieldLosesOnlyThatEventAndIsReported) {
  const std::vector<Damage> damages = {
      {"a zeroed sync byte", [](DamagedLog& l) { l.bytes[l.at(3, kSyncField)] = 0; }},
      {"the sync word gone", [](DamagedLog& l) { l.put_be32(l.at(3, kSyncField), 0x12345678); }},
      {"a negative event number", [](DamagedLog& l) { l.put_be64(l.at(3, kEventnumField), ~0ULL); }},
      {"a negative timestamp", [](DamagedLog& l) { l.put_be64(l.at(3, kTimestampField), 1ULL << 63); }},
      {"channel length 0", [](DamagedLog& l) { l.put_be32(l.at(3, kChannelLengthField), 0); }},
      {"channel length -1", [](DamagedLog& l) { l.put_be32(l.at(3, kChannelLengthField), 0xFFFFFFFF); }},
      {"channel length 0x7fffffff", [](DamagedLog& l) { l.put_be32(l.at(3, kChannelLengthField), 0x7FFFFFFF); }},
      {"channel length 256", [](DamagedLog& l) { l.put_be32(l.at(3, kChannelLengthField), 256); }},
      {"channel length one more", [](DamagedLog& l) { l.put_be32(l.at(3, kChannelLengthField), 15); }},
      {"channel length one less", [](DamagedLog& l) { l.put_be32(l.at(3, kChannelLengthField), 13); }},
      {"an unprintable channel byte", [](DamagedLog& l) { l.bytes[l.at(3, kChannelField + 2)] = '\n'; }},
      {"data length 0x7fffffff", [](DamagedLog& l) { l.put_be32(l.at(3, kDataLengthField), 0x7FFFFFFF); }},
      {"data length -1", [](DamagedLog& l) { l.put_be32(l.at(3, kDataLengthField), 0xFFFFFFFF); }},
      {"data length 0", [](DamagedLog& l) { l.put_be32(l.at(3, kDataLengthField), 0); }},
      {"data length past the end of the file",
       [](DamagedLog& l) { l.put_be32(l.at(3, kDataLengthField), static_cast<std::uint32_t>(l.bytes.size())); }},
      {"data length one event longer",
       [](DamagedLog& l) {
         const std::size_t data = l.event_bytes - kChannelField - kChannel.size();
         l.put_be32(l.at(3, kDataLengthField), static_cast<std::uint32_t>(data + l.event_bytes));
       }},
      {"data length one byte shorter",
       [](DamagedLog& l) {
         const std::size_t data = l.event_bytes - kChannelField - kChannel.size();
         l.put_be32(l.at(3, kDataLengthField), static_cast<std::uint32_t>(data - 1));
       }},
  };
  for (const Damage& d : damages) {
    SCOPED_TRACE(d.what);
    DamagedLog log;
    ASSERT_EQ(log.event_bytes * DamagedLog::kFrames, log.bytes.size());
    d.apply(log);
    const DamagedLog::Outcome o = log.read();
    EXPECT_EQ(o.sequences, (std::vector<std::uint64_t>{0, 1, 2, 4, 5})) << o.problems;
    EXPECT_GE(o.damaged + o.lost_reports, 1u) << "the damage is reported";
    EXPECT_GE(o.damaged + o.lost_events, 1u) << "the lost frame is counted";
    EXPECT_FALSE(o.truncated);
  }
}

TEST(FrameLog, AHugeDataLengthIsNamedAndSkippedNotAllocated) {
  DamagedLog log;
  log.put_be32(log.at(3, kDataLengthField), 0x7FFFFFFF);
  const DamagedLog::Outcome o = log.read();
  EXPECT_EQ(o.lost_reports, 1u);
  EXPECT_EQ(o.lost_events, 1u);
  EXPECT_NE(o.problems.find(": damaged: bytes " + std::to_string(log.at(3, 0)) + ".." + std::to_string(log.at(4, 0))),
            std::string::npos)
      << o.problems;
  EXPECT_NE(o.problems.find("data length 2147483647 is not within 0..268435456"), std::string::npos) << o.problems;
}

TEST(FrameLog, DamageInTwoEventsInARowIsOneRegionOfTwoEvents) {
  DamagedLog log;
  log.put_be32(log.at(2, kDataLengthField), 0x7FFFFFFF);
  log.put_be64(log.at(3, kTimestampField), ~0ULL);
  const DamagedLog::Outcome o = log.read();
  EXPECT_EQ(o.sequences, (std::vector<std::uint64_t>{0, 1, 4, 5}));
  EXPECT_EQ(o.lost_reports, 1u);
  EXPECT_EQ(o.lost_events, 2u) << "the second event's sync word counts it";
}

TEST(FrameLog, ACutLastEventIsReportedAsTruncatedWhereverItIsCut) {
  DamagedLog whole;
  for (const std::size_t keep : {std::size_t{2}, std::size_t{4}, kChannelField - 1, kChannelField + 3,
                                 kChannelField + kChannel.size() + 10, whole.event_bytes - 1}) {
    SCOPED_TRACE("last event cut after " + std::to_string(keep) + " bytes");
    DamagedLog log;
    log.bytes.resize(log.at(5, keep));
    const DamagedLog::Outcome o = log.read();
    EXPECT_EQ(o.sequences, (std::vector<std::uint64_t>{0, 1, 2, 3, 4}));
    EXPECT_EQ(o.lost_reports, 1u);
    EXPECT_EQ(o.lost_events, 1u);
    if (keep >= 4) {
      EXPECT_TRUE(o.truncated);
      EXPECT_NE(o.problems.find("is cut short"), std::string::npos) << o.problems;
    }
  }
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
