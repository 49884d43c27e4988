// Binary PGM and PPM (P6): exact bytes on disk, round trips at both depths and in colour, headers with comments,
// strided buffers, every kind of damaged file with its reason, and reads that allocate nothing.
#include "drivers/frames/pgm.hpp"

#include <sys/stat.h>

#include <cstring>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.hpp"
#include "tests/support/image_buffer.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

using Buffer = test::ImageBuffer;

TEST(Pgm, Writes8BitExactlyAndReadsItBack) {
  test::TempDir dir;
  Buffer src(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) src.view.row(y)[x] = static_cast<std::uint8_t>(10 * y + x + (x == 2 ? 200 : 0));
  const std::string path = dir.file("a.pgm");
  write_pgm(path, src.view);
  const std::string bytes = slurp(path);
  ASSERT_EQ(bytes.substr(0, 11), "P5\n5 3\n255\n");
  ASSERT_EQ(bytes.size(), 11u + 15u);
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[11 + 5 + 2]), 212);

  Buffer back(5, 3);
  PgmReader reader;
  PgmHeader h;
  ASSERT_EQ(reader.read(path.c_str(), back.view, &h), PgmFault::none) << reader.error();
  EXPECT_EQ(h.maxval, 255);
  EXPECT_EQ(back.bytes, src.bytes);
}

TEST(Pgm, ColourIsWrittenAsRgbPpmAndReadBackAsRgb8) {
  test::TempDir dir;
  Buffer src(3, 2, PixelFormat::bgr8);
  for (std::size_t i = 0; i < src.bytes.size(); ++i) src.bytes[i] = static_cast<std::uint8_t>(i + 1);
  const std::string path = dir.file("c.ppm");
  write_pgm(path, src.view);
  const std::string bytes = slurp(path);
  ASSERT_EQ(bytes.substr(0, 11), "P6\n3 2\n255\n");
  ASSERT_EQ(bytes.size(), 11u + 18u);
  // The first pixel is B 1, G 2, R 3 in memory: on disk R G B.
  EXPECT_EQ(bytes.substr(11, 3), std::string("\3\2\1"));

  Buffer back(3, 2, PixelFormat::rgb8, 5);
  PgmReader reader;
  PgmHeader h;
  ASSERT_EQ(reader.read(path.c_str(), back.view, &h), PgmFault::none) << reader.error();
  EXPECT_EQ(h.channels, 3);
  EXPECT_EQ(h.format(), PixelFormat::rgb8);
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 3; ++x)
      for (int c = 0; c < 3; ++c)
        EXPECT_EQ(back.view.row(y)[3 * x + c], src.view.row(y)[3 * x + 2 - c]) << x << "," << y << "," << c;
  EXPECT_EQ(back.view.row(0)[9], 0xEE) << "the padding is untouched";
}

TEST(Pgm, Writes16BitBigEndianAndReadsNativeValues) {
  test::TempDir dir;
  Buffer src(3, 2, PixelFormat::mono16);
  src.view.significant_bits = 12;
  const std::uint16_t values[6] = {0, 1, 0x0123, 0x0ABC, 4095, 2048};
  std::memcpy(src.bytes.data(), values, sizeof values);
  const std::string path = dir.file("w.pgm");
  write_pgm(path, src.view);
  const std::string bytes = slurp(path);
  ASSERT_EQ(bytes.substr(0, 12), "P5\n3 2\n4095\n");
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[12 + 4]), 0x01);  // 0x0123, high byte first
  EXPECT_EQ(static_cast<std::uint8_t>(bytes[12 + 5]), 0x23);

  Buffer back(3, 2, PixelFormat::mono16);
  PgmReader reader;
  PgmHeader h;
  ASSERT_EQ(reader.read(path.c_str(), back.view, &h), PgmFault::none) << reader.error();
  EXPECT_EQ(h.maxval, 4095);
  EXPECT_EQ(h.significant_bits(), 12);
  EXPECT_EQ(std::memcmp(back.bytes.data(), values, sizeof values), 0);
}

TEST(Pgm, HeaderCommentsAndARasterStartingWithWhitespace) {
  test::TempDir dir;
  // Raster bytes '\n', ' ', '#' right after the single separator must be pixels.
  const std::string file = std::string("P5\n# made by hand\n4 # width\n# and now\n2\n255\n") + "\n #\tABCD";
  const std::string path = dir.write("c.pgm", file);
  Buffer b(4, 2);
  PgmReader reader;
  ASSERT_EQ(reader.read(path.c_str(), b.view), PgmFault::none) << reader.error();
  EXPECT_EQ(b.view.row(0)[0], '\n');
  EXPECT_EQ(b.view.row(0)[1], ' ');
  EXPECT_EQ(b.view.row(0)[2], '#');
  EXPECT_EQ(b.view.row(1)[3], 'D');
}

TEST(Pgm, DecodesIntoAStridedBufferWithoutTouchingThePadding) {
  test::TempDir dir;
  const std::string path = dir.write("s.pgm", std::string("P5 3 2 255 ") + "abcdef");
  Buffer b(3, 2, PixelFormat::mono8, 5);
  PgmReader reader;
  ASSERT_EQ(reader.read(path.c_str(), b.view), PgmFault::none) << reader.error();
  EXPECT_EQ(std::string(reinterpret_cast<char*>(b.view.row(0)), 3), "abc");
  EXPECT_EQ(std::string(reinterpret_cast<char*>(b.view.row(1)), 3), "def");
  EXPECT_EQ(b.view.row(0)[3], 0xEE);
  EXPECT_EQ(b.view.row(1)[7], 0xEE);
}

struct Damaged {
  const char* name;
  std::string content;  // empty name -> file not created
  PgmFault fault;
  const char* reason;
};

TEST(Pgm, DamagedFilesNameTheFileAndTheReason) {
  test::TempDir dir;
  const std::vector<Damaged> cases = {
      {"empty", "", PgmFault::truncated, "truncated: the file is empty"},
      {"ascii", "P2\n4 2\n255\n1 2 3 4 5 6 7 8\n", PgmFault::bad_header, "ASCII PGM (P2)"},
      {"magic", "P7\n4 2\n255\n", PgmFault::bad_header, "no P5 or P6 magic"},
      {"ascii-ppm", "P3\n4 2\n255\n", PgmFault::bad_header, "ASCII PPM (P3)"},
      {"deep-ppm", "P6\n4 2\n1023\n", PgmFault::bad_header, "16-bit PPM"},
      {"colour", "P6\n4 2\n255\n" + std::string(24, 'c'), PgmFault::wrong_depth,
       "wrong depth: colour PPM (maxval 255), expected 8-bit grey frames"},
      {"nomaxval", "P5\n4 2\n", PgmFault::bad_header, "header ends before the maxval"},
      {"letters", "P5\n4 x\n255\n", PgmFault::bad_header, "height is not a number"},
      {"zero", "P5\n0 2\n255\n", PgmFault::bad_header, "width is 0"},
      {"maxval", "P5\n4 2\n70000\n", PgmFault::bad_header, "maxval above 65535"},
      {"glued", "P5\n4 2\n255x12345678", PgmFault::bad_header, "no whitespace after the maxval"},
      {"size", "P5\n5 2\n255\n0123456789", PgmFault::wrong_size, "wrong size: 5x2, expected 4x2"},
      {"depth", "P5\n4 2\n1023\n0123456789abcdef", PgmFault::wrong_depth, "wrong depth: 16-bit grey PGM (maxval 1023)"},
      {"short", "P5\n4 2\n255\n01234", PgmFault::truncated, "truncated: 5 of 8 raster bytes"},
      {"long-header", "P5\n#" + std::string(5000, 'c') + "\n4 2\n255\n01234567", PgmFault::bad_header,
       "longer than 4096 bytes"},
  };
  PgmReader reader;
  for (const Damaged& c : cases) {
    const std::string path = dir.write(std::string(c.name) + ".pgm", c.content);
    Buffer b(4, 2);
    EXPECT_EQ(reader.read(path.c_str(), b.view), c.fault) << c.name << ": " << reader.error();
    const std::string err(reader.error());
    EXPECT_NE(err.find(path + ": "), std::string::npos) << err;
    EXPECT_NE(err.find(c.reason), std::string::npos) << c.name << ": " << err;
  }
  Buffer b(4, 2);
  const std::string missing = dir.file("nothere.pgm");
  EXPECT_EQ(reader.read(missing.c_str(), b.view), PgmFault::missing);
  EXPECT_EQ(std::string(reader.error()), missing + ": missing (no such file)");
  EXPECT_EQ(reader.read(dir.path().c_str(), b.view), PgmFault::unreadable);
  // A FIFO in a frame's place (no writer): refused at once, not waited on for ever.
  const std::string fifo = dir.file("fifo.pgm");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(reader.read(fifo.c_str(), b.view), PgmFault::unreadable);
  EXPECT_EQ(std::string(reader.error()), fifo + ": not a regular file");
  // A good read after the failures clears the message.
  const std::string good = dir.write("good.pgm", "P5 4 2 255\n01234567");
  EXPECT_EQ(reader.read(good.c_str(), b.view), PgmFault::none);
  EXPECT_TRUE(reader.error().empty());
}

TEST(Pgm, ProbeReadsOnlyTheHeader) {
  test::TempDir dir;
  const std::string path = dir.write("p.pgm", "P5\n1280 720\n65535\n");  // no raster at all
  PgmReader reader;
  PgmHeader h;
  ASSERT_EQ(reader.probe(path.c_str(), h), PgmFault::none) << reader.error();
  EXPECT_EQ(h.width, 1280);
  EXPECT_EQ(h.height, 720);
  EXPECT_EQ(h.format(), PixelFormat::mono16);
  EXPECT_EQ(h.significant_bits(), 16);
}

TEST(Pgm, ReadingAFrameAllocatesNothing) {
  test::TempDir dir;
  Buffer src(64, 48, PixelFormat::mono16);
  src.view.significant_bits = 10;
  write_pgm(dir.file("f.pgm"), src.view);
  const std::string path = dir.file("f.pgm"), missing = dir.file("none.pgm");
  Buffer into(64, 48, PixelFormat::mono16);
  Buffer wrong(32, 48, PixelFormat::mono16);
  PgmReader reader;
  test::AllocationScope scope;
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(reader.read(path.c_str(), into.view), PgmFault::none);
    EXPECT_EQ(reader.read(missing.c_str(), into.view), PgmFault::missing);
    EXPECT_EQ(reader.read(path.c_str(), wrong.view), PgmFault::wrong_size);
  }
  EXPECT_EQ(scope.count(), 0u);
}

TEST(Pgm, WriteFailureLeavesNoFile) {
  test::TempDir dir;
  Buffer src(4, 2);
  EXPECT_THROW(write_pgm(dir.file("no/such/dir/x.pgm"), src.view), std::runtime_error);
  EXPECT_THROW(write_pgm(dir.file("e.pgm"), ImageView{}), std::runtime_error);
  EXPECT_FALSE(std::ifstream(dir.file("e.pgm")).good());
  EXPECT_FALSE(std::ifstream(dir.file("e.pgm.tmp")).good());
}

}  // namespace
}  // namespace ccdlane
