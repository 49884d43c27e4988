// Reading pictures as grey: the Udacity JPEGs, PNGs the overlay writes, 8- and 16-bit PGM, and garbage.
#include "tools/ccdlane/grey_picture.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <fstream>
#include <iterator>

#include <gtest/gtest.h>

#include "drivers/frames/pgm.hpp"
#include "tests/support/run_process.hpp"
#include "tools/ccdlane/overlay_png.hpp"

namespace ccdlane::cli {
namespace {

const std::string kUdacityDir = std::string(CCDLANE_SOURCE_DIR) + "/tests/data/real/udacity-advanced-chessboard/";

TEST(GreyPicture, ReadsJpegAtItsSize) {
  const GreyPicture a = read_grey_picture(kUdacityDir + "calibration2.jpg");
  EXPECT_EQ(a.width, 1280);
  EXPECT_EQ(a.height, 720);
  ASSERT_EQ(a.pixels.size(), 1280u * 720u);
  // A white sheet with black squares: both ends of the grey scale occur.
  const auto [lo, hi] = std::minmax_element(a.pixels.begin(), a.pixels.end());
  EXPECT_LT(*lo, 60);
  EXPECT_GT(*hi, 180);
  const GreyPicture b = read_grey_picture(kUdacityDir + "calibration7.jpg");
  EXPECT_EQ(b.width, 1281);
  EXPECT_EQ(b.height, 721);
}

TEST(GreyPicture, ReadsPngAndPgmToTheSameGrey) {
  const test::TempDir dir;
  std::vector<std::uint8_t> grey(40 * 30);
  for (std::size_t i = 0; i < grey.size(); ++i) grey[i] = static_cast<std::uint8_t>(i * 7 % 251);
  const ImageView view{grey.data(), 40, 30, 40, PixelFormat::mono8, 8};
  write_pgm(dir.file("a.pgm"), view);
  Overlay(view).write_png(dir.file("a.png"));  // RGB with R = G = B
  for (const char* name : {"a.pgm", "a.png"}) {
    const GreyPicture p = read_grey_picture(dir.file(name));
    EXPECT_EQ(p.width, 40) << name;
    EXPECT_EQ(p.height, 30) << name;
    EXPECT_EQ(p.pixels, grey) << name;
  }
}

TEST(GreyPicture, ScalesSixteenBitPgmToEightBits) {
  const test::TempDir dir;
  const std::vector<std::uint16_t> deep{0, 1023, 512, 4095};
  write_pgm(dir.file("deep.pgm"),
            {reinterpret_cast<const std::uint8_t*>(deep.data()), 2, 2, 4, PixelFormat::mono16, 12});
  const GreyPicture p = read_grey_picture(dir.file("deep.pgm"));
  EXPECT_EQ(p.pixels, (std::vector<std::uint8_t>{0, 63, 31, 255}));
}

TEST(GreyPicture, RefusesWhatIsNotAPicture) {
  const test::TempDir dir;
  const std::string text = dir.write("notes.jpg", "not a picture\n");
  EXPECT_THROW(read_grey_picture(text), std::runtime_error);
  EXPECT_THROW(read_grey_picture(dir.file("missing.png")), std::runtime_error);
  // A JPEG cut short after its header.
  std::ifstream in(kUdacityDir + "calibration2.jpg", std::ios::binary);
  std::string bytes(2000, '\0');
  in.read(bytes.data(), 2000);
  const std::string cut = dir.write("cut.jpg", bytes);
  try {
    read_grey_picture(cut);
    ADD_FAILURE() << "a truncated JPEG was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cut.jpg: bad JPEG"), std::string::npos) << e.what();
  }
}

// Files that claim huge pictures are refused from their header, naming the file, before
// anything is allocated: a 35-byte PGM header of 65535x65535 (once 8.6 GB), the same with
// a size within the bound but more than the file holds, and a JPEG whose frame header
// says 60000x60000.
TEST(GreyPicture, AHugeClaimedSizeIsRefusedBeforeDecoding) {
  const test::TempDir dir;
  const std::string pgm = dir.write("huge.pgm", "P5\n65535 65535\n255\n" + std::string(16, 'x'));
  try {
    read_grey_picture(pgm);
    ADD_FAILURE() << "decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), pgm + ": 65535x65535 pixels: more than 40000000; not decoded");
  }
  const std::string claims = dir.write("claims.pgm", "P5\n6000 6000\n255\n" + std::string(16, 'x'));
  try {
    read_grey_picture(claims);
    ADD_FAILURE() << "decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(claims + ": truncated: its header says 6000x6000 pixels"), std::string::npos)
        << e.what();
  }
  std::ifstream in(kUdacityDir + "calibration2.jpg", std::ios::binary);
  std::string jpeg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t sof = jpeg.find("\xFF\xC0");
  ASSERT_NE(sof, std::string::npos) << "a baseline JPEG";
  for (const std::size_t at : {sof + 5, sof + 7}) {  // height, then width, big-endian
    jpeg[at] = static_cast<char>(0xEA);
    jpeg[at + 1] = static_cast<char>(0x60);
  }
  const std::string huge_jpeg = dir.write("huge.jpg", jpeg.substr(0, sof + 2000));
  try {
    read_grey_picture(huge_jpeg);
    ADD_FAILURE() << "decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), huge_jpeg + ": bad JPEG: 60000x60000 pixels: more than 40000000; not decoded");
  }
}

// A FIFO in a picture's place is refused at once, not waited on.
TEST(GreyPicture, AFifoIsNoPicture) {
  const test::TempDir dir;
  const std::string fifo = dir.file("fifo.jpg");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    read_grey_picture(fifo);
    ADD_FAILURE() << "read";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), fifo + ": cannot open the picture: not a regular file");
  }
}

}  // namespace
}  // namespace ccdlane::cli
