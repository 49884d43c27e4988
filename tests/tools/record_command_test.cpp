// `ccdlane record` from the synthetic road, a frame directory and Aravis' fake camera
// with the emulated 3DM-GX1, into frame directories and LCM logs; and `ccdlane replay`
// of an LCM log giving the same JSON Lines as the frame directory of the same frames.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <ccdlane/vehicle_state_t.hpp>
#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>

#include "bus/channels.hpp"
#include "bus/frame_log.hpp"
#include "drivers/frames/frame_directory.hpp"
#include "drivers/frames/png.hpp"
#include "tests/daemon/child_process.hpp"
#include "tests/daemon/private_network.hpp"
#include "tests/support/run_process.hpp"
#include "tests/support/test_video.hpp"

namespace ccdlane {
namespace {

const std::string kTool = CCDLANE_TOOL;
const std::string kReferenceCamera = CCDLANE_SOURCE_DIR "/tools/demo/reference-camera.toml";
const std::string kFrames = channel_name("CCDLANE_", Channel::frames);

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Replay's JSON Lines without latency_us, the one field that measures this run.
std::vector<std::string> replay(const std::string& config, const std::string& input) {
  const auto r = test::run_process({kTool, "replay", config, input});
  EXPECT_EQ(r.exit_status, 0) << r.err;
  std::vector<std::string> lines = lines_of(r.out);
  const std::regex latency(R"(,"latency_us":[0-9]+)");
  for (std::string& line : lines) {
    EXPECT_NE(line.find("\"latency_us\":"), std::string::npos) << line;
    line = std::regex_replace(line, latency, "");
  }
  return lines;
}

std::vector<FrameRecord> records_of(const std::string& log) {
  FrameLogReader reader(log, kFrames);
  std::vector<FrameRecord> records;
  for (FrameLogReader::Next n; (n = reader.next()) != FrameLogReader::Next::end;) {
    EXPECT_EQ(n, FrameLogReader::Next::frame) << reader.problem();
    records.push_back(reader.record());
  }
  return records;
}

void expect_missing_reported(const std::string& err, std::size_t missing) {
  const std::string line = std::to_string(missing) + " frames without a gyro reading";
  if (missing > 0)
    EXPECT_NE(err.find(line), std::string::npos) << err;
  else
    EXPECT_EQ(err.find("without a gyro reading"), std::string::npos) << err;
}

TEST(RecordCommand, SynthIntoALogAndADirectoryReplaysToTheSameEstimates) {
  test::TempDir dir;
  const std::string log = dir.file("drive.lcmlog"), frames = dir.file("drive");
  for (const std::string& out : {log, frames}) {
    const auto r =
        test::run_process({kTool, "record", "synth", "--config", kReferenceCamera, "--out", out, "--count", "24"});
    ASSERT_EQ(r.exit_status, 0) << r.err;
    EXPECT_NE(r.err.find("24 frames of 800x600 mono8"), std::string::npos) << r.err;
  }
  const std::vector<FrameRecord> records = records_of(log);
  ASSERT_EQ(records.size(), 24u);
  for (std::size_t k = 0; k < records.size(); ++k) {
    EXPECT_EQ(records[k].sequence, k);
    EXPECT_EQ(records[k].t_ns, std::llround(static_cast<double>(k) / 30.0 * 1e9));  // as SynthDrive times them
    EXPECT_TRUE(records[k].gyro.has_value());
    if (k > 0) {
      EXPECT_EQ(records[k].utime - records[0].utime, (records[k].t_ns - records[0].t_ns) / 1000);
    }
  }
  FrameDirectory d(frames);
  ASSERT_EQ(d.size(), 24u);
  EXPECT_TRUE(d.has_gyro_columns());

  const std::vector<std::string> from_log = replay(kReferenceCamera, log);
  const std::vector<std::string> from_directory = replay(kReferenceCamera, frames);
  ASSERT_EQ(from_log.size(), 24u);
  EXPECT_EQ(from_log, from_directory);
  const auto ok = std::count_if(from_log.begin(), from_log.end(),
                                [](const std::string& l) { return l.find("\"ok\":true") != std::string::npos; });
  EXPECT_GE(ok, 20) << "the comparison must be of real estimates";
}

TEST(RecordCommand, AFrameDirectoryBecomesALogOfTheSameFrames) {
  test::TempDir dir;
  ASSERT_EQ(
      test::run_process({kTool, "synth", kReferenceCamera, "--out", dir.file("road"), "--frames", "6"}).exit_status, 0);
  const auto r = test::run_process({kTool, "record", "frames:" + dir.file("road"), "--out", dir.file("road.lcmlog")});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::vector<FrameRecord> records = records_of(dir.file("road.lcmlog"));
  FrameDirectory d(dir.file("road"));
  ASSERT_EQ(records.size(), d.size());
  for (std::size_t k = 0; k < records.size(); ++k) {
    EXPECT_EQ(records[k].t_ns, d.row(k).t_ns);
    ASSERT_TRUE(records[k].gyro && d.row(k).gyro);
    EXPECT_EQ(records[k].gyro->roll_deg, d.row(k).gyro->roll_deg);
    EXPECT_EQ(records[k].gyro->pitch_deg, d.row(k).gyro->pitch_deg);
  }
  EXPECT_EQ(replay(kReferenceCamera, dir.file("road.lcmlog")), replay(kReferenceCamera, dir.file("road")));
}

// A frame directory with the vehicle's columns keeps them through `record`, into a log
// (frame_t's speed and indicator) and into another directory (its columns), so both
// replay with the speed and indicator the drive had.
TEST(RecordCommand, TheVehicleColumnsOfAFrameDirectoryAreRecorded) {
  test::TempDir dir;
  ASSERT_EQ(
      test::run_process({kTool, "synth", kReferenceCamera, "--out", dir.file("road"), "--frames", "4"}).exit_status, 0);
  // Two columns appended to each row: speeds 70, 71, (none), 73; indicators in turn.
  const char* indicators[] = {"none", "left", "right", "both"};
  std::istringstream csv(test::read_file(dir.file("road/frames.csv")));
  std::string rewritten, line;
  std::getline(csv, line);
  rewritten = line + ",speed_kmh,turn_indicator\n";
  for (int k = 0; std::getline(csv, line); ++k)
    rewritten += line + "," + (k == 2 ? "" : std::to_string(70 + k)) + "," + indicators[k] + "\n";
  dir.write("road/frames.csv", rewritten);

  ASSERT_EQ(
      test::run_process({kTool, "record", "frames:" + dir.file("road"), "--out", dir.file("road.lcmlog")}).exit_status,
      0);
  ASSERT_EQ(test::run_process({kTool, "record", "frames:" + dir.file("road"), "--out", dir.file("copy")}).exit_status,
            0);
  const std::vector<FrameRecord> records = records_of(dir.file("road.lcmlog"));
  FrameDirectory copy(dir.file("copy"));
  ASSERT_EQ(records.size(), 4u);
  ASSERT_EQ(copy.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) {
    const std::optional<double> speed = k == 2 ? std::nullopt : std::optional<double>(70.0 + static_cast<double>(k));
    const auto indicator = static_cast<TurnIndicator>(k);
    EXPECT_EQ(records[k].speed_kmh, speed) << "frame " << k;
    EXPECT_EQ(records[k].indicator, indicator) << "frame " << k;
    EXPECT_EQ(copy.row(k).speed_kmh, speed) << "frame " << k;
    EXPECT_EQ(copy.row(k).indicator, indicator) << "frame " << k;
  }
}

// `record --vehicle-state` from a camera (Aravis' fake) while a gateway publishes
// vehicle_state_t on a real bus (udpm in a private network namespace): the frames record
// its speed, yaw rate and indicator, into the log and into a directory's columns.
TEST(RecordCommand, ACameraRecordingTakesTheGatewaysVehicleStateFromTheBus) {
  if (const std::string why = test::enter_private_network(); !why.empty()) GTEST_SKIP() << why;
  lcm::LCM bus(test::kBusUrl);
  ASSERT_TRUE(bus.good());
  test::TempDir dir;
  const std::string config = dir.write("c.toml", "[lcm]\nurl = \"" + test::kBusUrl + "\"\n");
  vehicle_state_t state{};
  state.speed_mps = 15.0;
  state.has_yaw_rate = true;
  state.yaw_rate_radps = 0.05;
  state.turn_indicator = vehicle_state_t::TURN_INDICATOR_RIGHT;
  for (const std::string out : {"drive.lcmlog", "drive"}) {
    test::ChildProcess recorder({kTool, "record", "aravis:Fake_1", "--config", config, "--out", dir.file(out),
                                 "--count", "30", "--vehicle-state"},
                                {{}, "", dir.file(out + ".err"), {}});
    std::optional<int> status;
    for (const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
         !(status = recorder.wait_exit(0)) && std::chrono::steady_clock::now() < end;) {
      bus.publish("CCDLANE_VEHICLE", &state);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    if (!status) status = recorder.wait_exit(5000);
    ASSERT_TRUE(status.has_value()) << "record did not end";
    ASSERT_EQ(WEXITSTATUS(*status), 0) << test::read_file(dir.file(out + ".err"));
  }
  // The gateway's first message may come after the first frames: those have none.
  const std::vector<FrameRecord> records = records_of(dir.file("drive.lcmlog"));
  ASSERT_EQ(records.size(), 30u);
  EXPECT_TRUE(records.back().speed_kmh) << "the last frames were taken with the gateway publishing";
  for (const FrameRecord& r : records) {
    if (!r.speed_kmh) continue;
    EXPECT_DOUBLE_EQ(*r.speed_kmh, 54.0);
    EXPECT_EQ(r.yaw_rate_radps, 0.05);
    EXPECT_EQ(r.indicator, TurnIndicator::right);
  }
  FrameDirectory d(dir.file("drive"));
  ASSERT_EQ(d.size(), 30u);
  EXPECT_TRUE(d.row(d.size() - 1).speed_kmh);
  for (std::size_t k = 0; k < d.size(); ++k)
    if (d.row(k).speed_kmh) {
      EXPECT_DOUBLE_EQ(*d.row(k).speed_kmh, 54.0);
      EXPECT_EQ(d.row(k).indicator, TurnIndicator::right);
    }
}

// Colour is kept: the real colour pictures recorded into a frame directory come out as
// PNG frames with the same pixels.
TEST(RecordCommand, ColourFramesAreRecordedAsPngWithTheirPixels) {
  test::TempDir dir;
  const std::string real = CCDLANE_TEST_DATA_DIR "/real/udacity-p1-colour";
  const auto r = test::run_process({kTool, "record", "frames:" + real, "--out", dir.file("copy")});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  EXPECT_NE(r.err.find("6 frames of 960x540 colour"), std::string::npos) << r.err;
  FrameDirectory from(real), to(dir.file("copy"));
  ASSERT_EQ(to.size(), from.size());
  for (std::size_t k = 0; k < to.size(); ++k) {
    EXPECT_EQ(std::filesystem::path(to.row(k).file).extension(), ".png");
    EXPECT_EQ(to.row(k).t_ns, from.row(k).t_ns);
    const OwnedPicture a = read_png_picture(from.file_path(k)), b = read_png_picture(to.file_path(k));
    EXPECT_EQ(b.format, PixelFormat::rgb8);
    EXPECT_TRUE(a.pixels == b.pixels) << k;
  }
}

TEST(RecordCommand, SecondsCountFrameTime) {
  test::TempDir dir;
  const auto r = test::run_process({kTool, "record", "synth", "--out", dir.file("half.lcmlog"), "--seconds", "0.5"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  // 30 fps: frames at 0, 1/30, ... 14/30 s are within the first half second.
  EXPECT_EQ(records_of(dir.file("half.lcmlog")).size(), 15u);
}

TEST(RecordCommand, FakeCameraWithTheEmulatedGyroRecordsItsReadingsAtTheFramesTimes) {
  test::TempDir dir;
  // The emulated gyro reports the synthetic drive's attitude (as the daemon's demo does):
  // here a roll of 10 degrees amplitude over 4 s and no noise, so that what it recorded
  // can be checked against the drive's motion.
  const std::string config = dir.write("fake.toml",
                                       "[camera]\nNu = 640\nNv = 480\n[gyro]\ndevice = \"emulated\"\n"
                                       "[synth]\nroll_sway_deg = 10.0\nroll_period_s = 4.0\ngyro_noise_deg = 0.0\n");
  auto r = test::run_process(
      {kTool, "record", "aravis:Fake_1", "--config", config, "--out", dir.file("fake.lcmlog"), "--count", "12"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::vector<FrameRecord> records = records_of(dir.file("fake.lcmlog"));
  ASSERT_EQ(records.size(), 12u);
  // On a loaded machine the emulator or the gyro thread can be starved for longer than the
  // history's 100 ms age limit: frames in such a gap get no reading, the recording counts
  // them and goes on. The readings there are must follow the emulator's turn.
  std::vector<const FrameRecord*> with_gyro;
  for (std::size_t k = 0; k < records.size(); ++k) {
    if (records[k].gyro) with_gyro.push_back(&records[k]);
    if (k == 0) continue;
    EXPECT_GT(records[k].sequence, records[k - 1].sequence);
    EXPECT_GT(records[k].t_ns, records[k - 1].t_ns);
  }
  ASSERT_GE(with_gyro.size(), records.size() / 2);
  expect_missing_reported(r.err, records.size() - with_gyro.size());
  // roll = 10 sin(2 pi t / 4 s + phase): within +-10 (plus the GX1's 0.01 degree
  // resolution), and over the recording's span s it changes by at least 10 (1 - cos(2 pi
  // s / 4)), what it changes by at the least when the span is centred on a peak.
  double lo = 1e9, hi = -1e9;
  for (const FrameRecord* f : with_gyro) {
    EXPECT_LE(std::abs(f->gyro->roll_deg), 10.05);
    lo = std::min(lo, f->gyro->roll_deg);
    hi = std::max(hi, f->gyro->roll_deg);
  }
  const double span_s = static_cast<double>(with_gyro.back()->t_ns - with_gyro.front()->t_ns) * 1e-9;
  EXPECT_GE(hi - lo, 0.9 * 10.0 * (1.0 - std::cos(2.0 * M_PI * span_s / 4.0)))
      << "the readings follow the drive's roll over " << span_s << " s";

  r = test::run_process(
      {kTool, "record", "aravis:Fake_1", "--config", config, "--out", dir.file("fake"), "--count", "5"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  FrameDirectory d(dir.file("fake"));
  ASSERT_EQ(d.size(), 5u);
  EXPECT_TRUE(d.has_gyro_columns());
  std::size_t rows_with_gyro = 0;
  for (std::size_t k = 0; k < d.size(); ++k) rows_with_gyro += d.row(k).gyro.has_value();
  EXPECT_GE(rows_with_gyro, 1u);
  expect_missing_reported(r.err, d.size() - rows_with_gyro);
}

TEST(RecordCommand, SigintFinishesTheRecordingCleanly) {
  test::TempDir dir;
  const std::string log = dir.file("live.lcmlog");
  test::ChildProcess recorder({kTool, "record", "aravis:Fake_1", "--out", log}, {{}, "", dir.file("err"), {}});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  recorder.signal(SIGINT);
  const auto status = recorder.wait_exit(5000);
  ASSERT_TRUE(status.has_value());
  ASSERT_TRUE(WIFEXITED(*status)) << test::read_file(dir.file("err"));
  EXPECT_EQ(WEXITSTATUS(*status), 0) << test::read_file(dir.file("err"));
  EXPECT_FALSE(std::filesystem::exists(log + ".tmp"));
  EXPECT_GT(records_of(log).size(), 10u);
}

// An ssh session that drops sends SIGHUP: the recording is finished as on Ctrl-C (once
// only .tmp files were left), into a frame directory too.
TEST(RecordCommand, SighupFinishesTheRecordingCleanly) {
  test::TempDir dir;
  const std::string out = dir.file("live");
  test::ChildProcess recorder({kTool, "record", "aravis:Fake_1", "--out", out}, {{}, "", dir.file("err"), {}});
  std::this_thread::sleep_for(std::chrono::milliseconds(1500));
  recorder.signal(SIGHUP);
  const auto status = recorder.wait_exit(5000);
  ASSERT_TRUE(status.has_value());
  ASSERT_TRUE(WIFEXITED(*status)) << test::read_file(dir.file("err"));
  EXPECT_EQ(WEXITSTATUS(*status), 0) << test::read_file(dir.file("err"));
  FrameDirectory d(out);
  EXPECT_GT(d.size(), 10u);
  for (const auto& e : std::filesystem::directory_iterator(out))
    EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

// `record --out DIR` into a user's directory once replaced its 000000.pgm and removed a
// .tmp file of theirs: refused, and the directory is as it was.
TEST(RecordCommand, AUsersDirectoryWithAFrameNameIsRefusedUntouched) {
  test::TempDir dir;
  const std::string mine = dir.file("mine");
  std::filesystem::create_directory(mine);
  dir.write("mine/000000.pgm", "my picture");
  dir.write("mine/notes.tmp", "my notes");
  const auto r = test::run_process({kTool, "record", "synth", "--out", mine, "--count", "3"});
  EXPECT_EQ(r.exit_status, 2) << r.err;
  EXPECT_EQ(r.err,
            "ccdlane: " + mine + ": already holds 000000.pgm, a name a recording writes; choose another place\n");
  EXPECT_EQ(test::read_file(mine + "/000000.pgm"), "my picture");
  EXPECT_EQ(test::read_file(mine + "/notes.tmp"), "my notes");
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(mine), {}), 2);
}

TEST(RecordCommand, BadUseIsOneLineAndLeavesNothingBehind) {
  test::TempDir dir;
  auto r = test::run_process({kTool, "record", "usb:3", "--out", dir.file("x.lcmlog")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane: record: source \"usb:3\": expected v4l2:/dev/videoN or aravis:ID\n");
  const std::string taken = dir.write("taken.lcmlog", "x");
  r = test::run_process({kTool, "record", "synth", "--out", taken, "--count", "1"});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_EQ(r.err, "ccdlane: " + taken + ": already exists; choose another name\n");
  r = test::run_process({kTool, "record", "aravis:192.0.2.1", "--out", dir.file("none.lcmlog"), "--count", "1"});
  EXPECT_EQ(r.exit_status, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  r = test::run_process({kTool, "record", "frames:" + dir.file("nowhere"), "--out", dir.file("none.lcmlog")});
  EXPECT_EQ(r.exit_status, 2);
  EXPECT_NE(r.err.find(dir.file("nowhere") + "/frames.csv"), std::string::npos) << r.err;
  const std::string emulated = dir.write("g.toml", "[gyro]\ndevice = \"/nonexistent/ttyUSB9\"\n");
  r = test::run_process({kTool, "record", "aravis:Fake_1", "--config", emulated, "--out", dir.file("none")});
  EXPECT_EQ(r.exit_status, 1);
  // The daemon's gyro provider names the configuration key, as ccdlaned does.
  EXPECT_NE(r.err.find("gyro.device: \"/nonexistent/ttyUSB9\": /nonexistent/ttyUSB9: No such file"), std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  std::vector<std::string> left;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) left.push_back(e.path().filename());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"g.toml", "taken.lcmlog"}));
}

}  // namespace
}  // namespace ccdlane

namespace ccdlane {
namespace {

// `record` into a 2 MB tmpfs (a private mount namespace: root only) fills it after a
// few 800x600 frames. What was written is kept, whole, and replays; the command says how
// many frames were saved and exits 1.
void record_into_a_full_disk(const std::string& out_name) {
  if (::geteuid() != 0) GTEST_SKIP() << "needs root to mount a small tmpfs in a private mount namespace";
  test::TempDir dir;
  const std::string small = dir.file("small");
  std::filesystem::create_directory(small);
  const std::string script =
      "mount -t tmpfs -o size=2m tmpfs \"$1\" || exit 99; out=\"$1/$4\"; "
      "\"$2\" record synth --config \"$3\" --out \"$out\" --count 50; echo \"record rc=$?\"; ls \"$1\"; "
      "\"$2\" replay \"$3\" \"$out\" >/dev/null; echo \"replay rc=$?\"";
  const auto r = test::run_process({"/usr/bin/unshare", "-m", "--propagation", "private", "/bin/sh", "-c", script, "sh",
                                    small, CCDLANE_TOOL,
                                    std::string(CCDLANE_SOURCE_DIR) + "/tools/demo/reference-camera.toml", out_name});
  if (r.exit_status == 99) GTEST_SKIP() << "cannot mount a tmpfs here: " << r.err;
  EXPECT_NE(r.out.find("record rc=1\n"), std::string::npos) << r.out << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  const std::string saved = " frames before it are saved in " + small + "/" + out_name;
  const std::size_t at = r.err.find(saved);
  ASSERT_NE(at, std::string::npos) << r.err;
  const std::size_t number = r.err.rfind("the ", at) + 4;
  const int kept = std::stoi(r.err.substr(number, at - number));
  EXPECT_GE(kept, 2) << "a 2 MB disk holds a few 469 KiB frames";
  EXPECT_NE(r.out.find(out_name + "\n"), std::string::npos) << "kept under its final name: " << r.out;
  EXPECT_EQ(r.out.find(".tmp"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("replay rc=0\n"), std::string::npos) << "the kept frames are whole: " << r.out << r.err;
  EXPECT_NE(r.err.find("ccdlane replay: " + std::to_string(kept) + " frames, "), std::string::npos) << r.err;
}

TEST(RecordCommand, AFullDiskKeepsTheLogWrittenSoFar) { record_into_a_full_disk("drive.lcmlog"); }
TEST(RecordCommand, AFullDiskKeepsTheFrameDirectoryWrittenSoFar) { record_into_a_full_disk("drive"); }

}  // namespace
}  // namespace ccdlane

namespace ccdlane {
namespace {

// A dashcam's video into a log: its frames at the container's times, no gyro, and the
// constant --speed-kmh a dashcam cannot record, which replay of the log then drives with.
TEST(RecordCommand, AVideoBecomesALogWithTheGivenSpeed) {
  test::TempDir dir;
  const std::vector<std::int64_t> times = {0, 40'000'000, 80'000'000, 200'000'000, 240'000'000};
  const std::string video = test::write_test_video(dir.file("drive.mp4"), 800, 600, times);
  const std::string config = dir.write("camera.toml", "[prior]\nphi_deg = [0.0, 1.0]\n");
  const auto r = test::run_process(
      {kTool, "record", "video:" + video, "--config", config, "--out", dir.file("drive.lcmlog"), "--speed-kmh", "90"});
  ASSERT_EQ(r.exit_status, 0) << r.err;
  const std::vector<FrameRecord> records = records_of(dir.file("drive.lcmlog"));
  ASSERT_EQ(records.size(), times.size());
  for (std::size_t k = 0; k < records.size(); ++k) {
    EXPECT_EQ(records[k].sequence, k);
    EXPECT_EQ(records[k].t_ns, times[k]);
    EXPECT_FALSE(records[k].gyro.has_value());
    EXPECT_EQ(records[k].speed_kmh, 90.0);
  }
  for (const std::string& line : replay(config, dir.file("drive.lcmlog")))
    EXPECT_NE(line.find("\"speed_mps\":25.0"), std::string::npos) << line;
  // The camera of --config decides the size: a video of another is refused naming both.
  const std::string small = test::write_test_video(dir.file("small.mp4"), 64, 48, times);
  const auto refused =
      test::run_process({kTool, "record", "video:" + small, "--config", config, "--out", dir.file("y.lcmlog")});
  EXPECT_EQ(refused.exit_status, 2);
  EXPECT_EQ(refused.err, "ccdlane: " + small + ": frames are 64x48, the camera of " + config + " is 800x600\n");
  EXPECT_FALSE(std::filesystem::exists(dir.file("y.lcmlog")));
}

}  // namespace
}  // namespace ccdlane
