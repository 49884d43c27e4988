// Frame directories: the real pictures of the shared data, and a damaged recording whose
// every good frame is still read while each bad one is named with its reason.
#include "drivers/frames/frame_directory.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <vector>

#include <gtest/gtest.h>

#include "drivers/frames/frame_directory_writer.hpp"
#include "tests/support/allocation_counter.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

struct Frame {
  std::vector<std::uint8_t> bytes;
  MutableImageView view;
  Frame(int w, int h, PixelFormat f = PixelFormat::mono8)
      : bytes(static_cast<std::size_t>(w * h * bytes_per_pixel(f))) {
    view = {bytes.data(), w, h, w * bytes_per_pixel(f), f, f == PixelFormat::mono16 ? 16 : 8};
  }
};

TEST(FrameDirectory, ReadsTheRealUdacityFrames) {
  FrameDirectory dir(std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-advanced");
  ASSERT_EQ(dir.size(), 2u);
  EXPECT_TRUE(dir.issues().empty());
  EXPECT_FALSE(dir.has_gyro_columns());
  EXPECT_EQ(dir.row(1).t_ns, 50'000'000);
  const auto h = dir.probe_first();
  ASSERT_TRUE(h);
  EXPECT_EQ(h->width, 1280);
  EXPECT_EQ(h->height, 720);
  Frame f(1280, 720);
  for (std::size_t i = 0; i < dir.size(); ++i) {
    ASSERT_EQ(dir.read(i, f.view), PgmFault::none) << dir.error();
    // A road picture: not blank, a spread of grey levels.
    int lo = 255, hi = 0;
    for (std::uint8_t v : f.bytes) lo = std::min<int>(lo, v), hi = std::max<int>(hi, v);
    EXPECT_GT(hi - lo, 100);
  }
}

TEST(FrameDirectory, ReadsTheRealColourFramesAsRgb) {
  FrameDirectory dir(std::string(CCDLANE_TEST_DATA_DIR) + "/real/udacity-p1-colour");
  ASSERT_EQ(dir.size(), 6u);
  const auto h = dir.probe_first();
  ASSERT_TRUE(h);
  EXPECT_EQ(h->width, 960);
  EXPECT_EQ(h->height, 540);
  EXPECT_EQ(h->format(), PixelFormat::rgb8);
  Frame f(960, 540, PixelFormat::rgb8);
  for (std::size_t i = 0; i < dir.size(); ++i) {
    ASSERT_EQ(dir.read(i, f.view), PgmFault::none) << dir.error();
    // In colour: some pixels far from grey (the yellow line, the sky).
    int coloured = 0;
    for (std::size_t k = 0; k < f.bytes.size(); k += 3) coloured += std::abs(f.bytes[k] - f.bytes[k + 2]) > 60;
    EXPECT_GT(coloured, 1000);
  }
}

TEST(FrameDirectory, ColourFramesAreWrittenAsPngAndDamageIsCounted) {
  test::TempDir tmp;
  const std::string path = tmp.file("colour");
  Frame f(24, 10, PixelFormat::rgb8);
  {
    FrameDirectoryWriter w(path, {});
    for (int i = 0; i < 4; ++i) {
      for (std::size_t k = 0; k < f.bytes.size(); ++k) f.bytes[k] = static_cast<std::uint8_t>(k * 3 + i);
      w.write(f.view, i * 10);
    }
    w.finish();
  }
  std::ifstream csv(path + "/frames.csv");
  std::string header, first;
  std::getline(csv, header);
  std::getline(csv, first);
  EXPECT_EQ(first, "000000.png,0");
  // Damage: 1 cut short, 2 not a PNG at all.
  std::filesystem::resize_file(path + "/000001.png", std::filesystem::file_size(path + "/000001.png") / 2);
  std::ofstream(path + "/000002.png", std::ios::trunc) << "P6\n24 10\n255\n";
  FrameDirectory dir(path);
  ASSERT_EQ(dir.size(), 4u);
  EXPECT_EQ(dir.probe_first()->format(), PixelFormat::rgb8);
  std::vector<PgmFault> faults;
  for (std::size_t i = 0; i < dir.size(); ++i) {
    faults.push_back(dir.read(i, f.view));
    if (faults.back() == PgmFault::none) {
      for (std::size_t k = 0; k < f.bytes.size(); ++k) ASSERT_EQ(f.bytes[k], static_cast<std::uint8_t>(k * 3 + i));
    } else {
      EXPECT_EQ(dir.error().substr(0, path.size()), path) << dir.error();
    }
  }
  EXPECT_EQ(faults, (std::vector<PgmFault>{PgmFault::none, PgmFault::truncated, PgmFault::bad_header, PgmFault::none}));
}

TEST(FrameDirectory, WriterRoundTripsImagesGyroAndTruth) {
  test::TempDir tmp;
  const std::string path = tmp.file("rec");
  Frame f(8, 4);
  {
    FrameDirectoryWriter w(path, {true, {"truth_psi_deg", "truth_y0_0_mm"}});
    for (int i = 0; i < 3; ++i) {
      std::fill(f.bytes.begin(), f.bytes.end(), static_cast<std::uint8_t>(40 * i));
      const double truth[2] = {0.1 * i, i == 1 ? std::nan("") : 1750.0 + i};
      w.write(f.view, 1000 * i, i == 2 ? std::nullopt : std::optional<Gx1Angles>({1.5, -0.25 * i, 33.0}), truth);
    }
    EXPECT_FALSE(std::filesystem::exists(path + "/frames.csv"));  // not until finish()
    w.finish();
  }
  FrameDirectory dir(path);
  ASSERT_EQ(dir.size(), 3u);
  EXPECT_TRUE(dir.issues().empty());
  EXPECT_TRUE(dir.has_gyro_columns());
  EXPECT_EQ(dir.row(2).file, "000002.pgm");
  ASSERT_TRUE(dir.row(1).gyro);
  EXPECT_EQ(dir.row(1).gyro->pitch_deg, -0.25);
  EXPECT_EQ(dir.row(1).gyro->yaw_deg, 33.0);
  EXPECT_FALSE(dir.row(2).gyro);
  EXPECT_EQ(dir.truth(2, "truth_psi_deg").value(), 0.1 * 2);  // shortest round trip is exact
  EXPECT_FALSE(dir.truth(1, "truth_y0_0_mm"));
  EXPECT_EQ(dir.truth(2, "truth_y0_0_mm").value(), 1752.0);
  EXPECT_FALSE(dir.truth(0, "truth_nothing"));
  Frame back(8, 4);
  ASSERT_EQ(dir.read(1, back.view), PgmFault::none) << dir.error();
  EXPECT_EQ(back.bytes[5], 40);
}

TEST(FrameDirectory, WriterWrites16BitFrames) {
  test::TempDir tmp;
  Frame f(4, 2, PixelFormat::mono16);
  f.view.significant_bits = 12;
  const std::uint16_t v = 4000;
  std::memcpy(f.bytes.data() + 6, &v, 2);
  {
    FrameDirectoryWriter w(tmp.file("d"), {});
    w.write(f.view, 5);
    w.finish();
  }
  FrameDirectory dir(tmp.file("d"));
  EXPECT_EQ(dir.probe_first()->maxval, 4095);
  Frame back(4, 2, PixelFormat::mono16);
  ASSERT_EQ(dir.read(0, back.view), PgmFault::none) << dir.error();
  EXPECT_EQ(back.bytes, f.bytes);
}

TEST(FrameDirectory, AnUnfinishedWriterLeavesNothingBehind) {
  test::TempDir tmp;
  const std::string path = tmp.file("new/deeper");
  Frame f(4, 2);
  {
    FrameDirectoryWriter w(path, {});
    w.write(f.view, 0);
    w.write(f.view, 1);
    EXPECT_TRUE(std::filesystem::exists(path + "/000001.pgm"));
    EXPECT_THROW(w.write(f.view, 0), FrameDirectoryError);  // time going backwards
  }  // destroyed without finish(): e.g. an exception unwound the recording
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_TRUE(std::filesystem::exists(tmp.file("new")));  // parents are left alone

  // In an existing directory only its own files go.
  const std::string own = tmp.file("keep");
  std::filesystem::create_directory(own);
  tmp.write("keep/notes.txt", "mine");
  {
    FrameDirectoryWriter w(own, {});
    w.write(f.view, 0);
  }
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(own), {}), 1);
  EXPECT_TRUE(std::filesystem::exists(own + "/notes.txt"));
}

TEST(FrameDirectory, WriterRefusesToOverwriteARecording) {
  test::TempDir tmp;
  tmp.write("frames.csv", "file,t_ns\n");
  try {
    FrameDirectoryWriter w(tmp.path(), {});
    FAIL() << "no error";
  } catch (const FrameDirectoryError& e) {
    EXPECT_EQ(std::string(e.what()),
              tmp.path() + ": already holds a frame directory (frames.csv); choose another place");
  }
  EXPECT_THROW(FrameDirectoryWriter(tmp.file("frames.csv"), {}), FrameDirectoryError);  // not a directory
  EXPECT_THROW(FrameDirectoryWriter(tmp.file("x"), {false, {"psi"}}), FrameDirectoryError);
}

// `record --out DIR` into a user's directory once replaced its 000000.pgm and removed a
// .tmp file: a directory holding a name the writer writes is refused, untouched.
TEST(FrameDirectory, WriterRefusesADirectoryHoldingNamesItWrites) {
  for (const std::string name : {"000000.pgm", "000012.png", "frames.csv.tmp"}) {
    test::TempDir tmp;
    tmp.write(name, "mine");
    tmp.write("notes.txt", "mine too");
    try {
      FrameDirectoryWriter w(tmp.path(), {});
      FAIL() << name << ": no error";
    } catch (const FrameDirectoryError& e) {
      EXPECT_EQ(std::string(e.what()),
                tmp.path() + ": already holds " + name + ", a name a recording writes; choose another place");
    }
    EXPECT_EQ(std::distance(std::filesystem::directory_iterator(tmp.path()), {}), 2) << name;
  }
  // A frame name that appears after the start is not replaced either.
  test::TempDir tmp;
  Frame f(4, 2);
  FrameDirectoryWriter w(tmp.path(), {});
  w.write(f.view, 0);
  tmp.write("000001.pgm", "mine");
  EXPECT_THROW(w.write(f.view, 1), FrameDirectoryError);
  std::ifstream kept(tmp.file("000001.pgm"));
  std::string text;
  std::getline(kept, text);
  EXPECT_EQ(text, "mine");
}

TEST(FrameDirectory, DamagedRecordingKeepsEveryGoodFrame) {
  test::TempDir tmp;
  const std::string path = tmp.file("rec");
  Frame f(16, 8);
  {
    FrameDirectoryWriter w(path, {});
    for (int i = 0; i < 6; ++i) {
      std::fill(f.bytes.begin(), f.bytes.end(), static_cast<std::uint8_t>(i));
      w.write(f.view, i * 10);
    }
    w.finish();
  }
  // Damage: 1 missing, 2 truncated, 3 another size, plus a malformed row in frames.csv.
  std::filesystem::remove(path + "/000001.pgm");
  std::filesystem::resize_file(path + "/000002.pgm", 100);
  Frame big(20, 8);
  std::filesystem::remove(path + "/000003.pgm");
  {
    FrameDirectoryWriter other(tmp.file("other"), {});
    other.write(big.view, 0);
    other.finish();
  }
  std::filesystem::rename(tmp.file("other/000000.pgm"), path + "/000003.pgm");
  std::ofstream(path + "/frames.csv", std::ios::app) << "000005.pgm,oops\n";

  FrameDirectory dir(path);
  ASSERT_EQ(dir.size(), 6u);
  ASSERT_EQ(dir.issues().size(), 1u);
  EXPECT_EQ(dir.issues()[0], path + "/frames.csv:8: t_ns: not an integer: \"oops\"");
  std::vector<PgmFault> faults;
  std::vector<std::string> errors;
  for (std::size_t i = 0; i < dir.size(); ++i) {
    faults.push_back(dir.read(i, f.view));
    errors.emplace_back(dir.error());
    if (faults.back() == PgmFault::none) {
      EXPECT_EQ(f.bytes[0], i);
    }
  }
  EXPECT_EQ(faults, (std::vector<PgmFault>{PgmFault::none, PgmFault::missing, PgmFault::truncated, PgmFault::wrong_size,
                                           PgmFault::none, PgmFault::none}));
  EXPECT_EQ(errors[1], path + "/000001.pgm: missing (no such file)");
  EXPECT_EQ(errors[2], path + "/000002.pgm: truncated: 88 of 128 raster bytes");
  EXPECT_EQ(errors[3], path + "/000003.pgm: wrong size: 20x8, expected 16x8");
}

TEST(FrameDirectory, NoIndexIsAnError) {
  test::TempDir tmp;
  try {
    FrameDirectory dir(tmp.path() + "/");
    FAIL() << "no error";
  } catch (const FrameDirectoryError& e) {
    EXPECT_EQ(std::string(e.what()), tmp.path() +
                                         "/frames.csv: cannot read: No such file or directory (a frame directory "
                                         "needs frames.csv, or pictures to take in name order)");
  }
}

// A folder of pictures without frames.csv (a benchmark's stills as published): its
// pictures are the frames, in name order, 40 ms apart, whatever the case of their
// extensions; other files are not frames. The run is told so.
TEST(FrameDirectory, AFolderOfPicturesWithoutAnIndexIsReadInNameOrder) {
  test::TempDir tmp;
  const std::string stills = std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/images";
  std::filesystem::copy_file(stills + "/0002.jpg", tmp.file("b.jpg"));
  std::filesystem::copy_file(stills + "/0000.jpg", tmp.file("c.JPEG"));
  std::filesystem::copy_file(stills + "/0001.jpg", tmp.file("a.jpg"));
  std::ofstream(tmp.file("notes.txt")) << "not a frame\n";
  std::ofstream(tmp.file("._a.jpg")) << "AppleDouble metadata, not a JPEG";  // hidden: not a frame
  std::ofstream(tmp.file(".jpg")) << "";
  std::filesystem::create_directory(tmp.file("d.png"));  // a folder, whatever its name
  FrameDirectory dir(tmp.path());
  ASSERT_EQ(dir.size(), 3u);
  EXPECT_EQ(dir.data_rows(), 3u);
  EXPECT_TRUE(dir.issues().empty());
  const char* names[] = {"a.jpg", "b.jpg", "c.JPEG"};
  Frame f(1280, 720, PixelFormat::rgb8);
  for (std::size_t i = 0; i < dir.size(); ++i) {
    EXPECT_EQ(dir.row(i).file, names[i]);
    EXPECT_EQ(dir.row(i).index, i);
    EXPECT_EQ(dir.row(i).t_ns, static_cast<std::int64_t>(i) * 40'000'000);
    EXPECT_EQ(dir.file_path(i), tmp.file(names[i]));
    EXPECT_EQ(dir.read(i, f.view), PgmFault::none) << dir.error();
  }
  EXPECT_EQ(dir.note(), tmp.path() + ": no frames.csv: its 3 pictures in name order, 40 ms apart");

  // Numbers in names by their value: a clip's 1.jpg ... 20.jpg play 2 before 10.
  test::TempDir clip;
  for (const char* name : {"10.jpg", "2.jpg", "1.jpg", "20.jpg", "02b.jpg"})
    std::filesystem::copy_file(stills + "/0000.jpg", clip.file(name));
  const FrameDirectory played(clip.path());
  std::vector<std::string> order;
  for (std::size_t i = 0; i < played.size(); ++i) order.push_back(played.row(i).file);
  EXPECT_EQ(order, (std::vector<std::string>{"1.jpg", "2.jpg", "02b.jpg", "10.jpg", "20.jpg"}));

  // With frames.csv, that is the index, and there is nothing to note.
  std::ofstream(tmp.file("frames.csv")) << "file,t_ns\nb.jpg,0\n";
  const FrameDirectory indexed(tmp.path());
  EXPECT_EQ(indexed.size(), 1u);
  EXPECT_EQ(indexed.note(), "");
}

// frames.csv a FIFO (no writer): replay once hung for ever in open().
TEST(FrameDirectory, AFifoAsTheIndexIsRefusedAtOnce) {
  test::TempDir tmp;
  ASSERT_EQ(::mkfifo(tmp.file("frames.csv").c_str(), 0600), 0);
  try {
    FrameDirectory dir(tmp.path());
    FAIL() << "no error";
  } catch (const FrameDirectoryError& e) {
    EXPECT_EQ(std::string(e.what()),
              tmp.path() + "/frames.csv: cannot read: not a regular file (a frame directory needs frames.csv)");
  }
}

TEST(FrameDirectory, ReadingAllocatesNothing) {
  test::TempDir tmp;
  Frame f(32, 16);
  {
    FrameDirectoryWriter w(tmp.file("d"), {});
    w.write(f.view, 0);
    w.write(f.view, 1);
    w.finish();
  }
  std::filesystem::remove(tmp.file("d/000001.pgm"));
  FrameDirectory dir(tmp.file("d"));
  test::AllocationScope scope;
  for (int k = 0; k < 5; ++k) {
    EXPECT_EQ(dir.read(0, f.view), PgmFault::none);
    EXPECT_EQ(dir.read(1, f.view), PgmFault::missing);
  }
  EXPECT_EQ(scope.count(), 0u);
}

}  // namespace
}  // namespace ccdlane
