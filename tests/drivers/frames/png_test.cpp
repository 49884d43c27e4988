// PNG frames: grey and RGB round trips (exact, strided buffers), palette and alpha
// pictures turned into frames, 16-bit refused, every kind of damaged file with its
// reason, and reads that allocate nothing.
#include "drivers/frames/png.hpp"

#include <png.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/allocation_counter.hpp"
#include "tests/support/image_buffer.hpp"
#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

using Buffer = test::ImageBuffer;

// A picture with texture (so that compression has work and damage lands in real data).
void fill_pattern(Buffer& b, unsigned seed) {
  for (int y = 0; y < b.view.height; ++y)
    for (int x = 0; x < b.view.width * bytes_per_pixel(b.view.format); ++x)
      b.view.row(y)[x] = static_cast<std::uint8_t>((x * 7 + y * 13 + seed * 31 + ((x * y) >> 3)) & 0xFF);
}

// The picture's pixels only (not a stride's padding).
std::vector<std::uint8_t> pixels(const MutableImageView& v) {
  std::vector<std::uint8_t> out;
  for (int y = 0; y < v.height; ++y) out.insert(out.end(), v.row(y), v.row(y) + v.width * bytes_per_pixel(v.format));
  return out;
}

// A PNG in a layout frames do not use directly, written with libpng's simplified API.
void write_with_format(const std::string& path, png_uint_32 format, int w, int h, const void* data) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(w);
  png.height = static_cast<png_uint_32>(h);
  png.format = format;
  ASSERT_NE(png_image_write_to_file(&png, path.c_str(), 0, data, 0, nullptr), 0) << png.message;
}

TEST(Png, GreyRoundTripsExactly) {
  test::TempDir dir;
  Buffer src(37, 11);
  fill_pattern(src, 1);
  const std::string path = dir.file("g.png");
  write_png(path, src.view);
  PngReader reader;
  PgmHeader h;
  ASSERT_EQ(reader.probe(path.c_str(), h), PgmFault::none) << reader.error();
  EXPECT_EQ(h.width, 37);
  EXPECT_EQ(h.height, 11);
  EXPECT_EQ(h.format(), PixelFormat::mono8);
  Buffer back(37, 11);
  ASSERT_EQ(reader.read(path.c_str(), back.view, &h), PgmFault::none) << reader.error();
  EXPECT_EQ(back.bytes, src.bytes);
}

TEST(Png, RgbAndBgrRoundTripAsRgb8IntoAStridedBuffer) {
  test::TempDir dir;
  for (const int level : {0, 1, 6, 9}) {
    SCOPED_TRACE(level);
    Buffer src(29, 7, PixelFormat::rgb8);
    fill_pattern(src, 2);
    const std::string path = dir.file("c.png");
    write_png(path, src.view, level);
    Buffer back(29, 7, PixelFormat::rgb8, 5);
    PngReader reader;
    PgmHeader h;
    ASSERT_EQ(reader.read(path.c_str(), back.view, &h), PgmFault::none) << reader.error();
    EXPECT_EQ(h.channels, 3);
    EXPECT_EQ(pixels(back.view), pixels(src.view));
    for (int y = 0; y < 7; ++y)  // the padding of each row is left alone
      for (int k = 0; k < 5; ++k) EXPECT_EQ(back.view.row(y)[29 * 3 + k], 0xEE);
  }
  // bgr8 is written in RGB order: read back, each pixel's bytes are swapped.
  Buffer bgr(4, 3, PixelFormat::bgr8);
  fill_pattern(bgr, 3);
  write_png(dir.file("b.png"), bgr.view);
  const OwnedPicture back = read_png_picture(dir.file("b.png"));
  ASSERT_EQ(back.format, PixelFormat::rgb8);
  for (std::size_t i = 0; i < bgr.bytes.size(); i += 3) {
    EXPECT_EQ(back.pixels[i], bgr.bytes[i + 2]);
    EXPECT_EQ(back.pixels[i + 1], bgr.bytes[i + 1]);
    EXPECT_EQ(back.pixels[i + 2], bgr.bytes[i]);
  }
}

TEST(Png, PaletteAndAlphaBecomeRgbOrGreyFrames) {
  test::TempDir dir;
  // RGBA: alpha dropped, colour kept.
  const std::uint8_t rgba[2 * 2 * 4] = {10, 20, 30, 255, 40, 50, 60, 0, 70, 80, 90, 128, 100, 110, 120, 1};
  write_with_format(dir.file("rgba.png"), PNG_FORMAT_RGBA, 2, 2, rgba);
  Buffer rgb(2, 2, PixelFormat::rgb8);
  PngReader reader;
  ASSERT_EQ(reader.read(dir.file("rgba.png").c_str(), rgb.view), PgmFault::none) << reader.error();
  EXPECT_EQ(rgb.bytes, (std::vector<std::uint8_t>{10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120}));
  // Grey with alpha: grey.
  const std::uint8_t ga[3 * 4] = {5, 255, 6, 0, 7, 9, 250, 200};
  write_with_format(dir.file("ga.png"), PNG_FORMAT_GA, 4, 1, ga);
  Buffer grey(4, 1);
  ASSERT_EQ(reader.read(dir.file("ga.png").c_str(), grey.view), PgmFault::none) << reader.error();
  EXPECT_EQ(grey.bytes, (std::vector<std::uint8_t>{5, 6, 7, 250}));
  // A palette picture: its colours, as RGB.
  const std::uint8_t colours[3 * 3] = {255, 0, 0, 0, 255, 0, 0, 0, 255};
  const std::uint8_t index[4] = {0, 1, 2, 1};
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = 4;
  png.height = 1;
  png.format = PNG_FORMAT_RGB_COLORMAP;
  png.colormap_entries = 3;
  ASSERT_NE(png_image_write_to_file(&png, dir.file("pal.png").c_str(), 0, index, 0, colours), 0) << png.message;
  Buffer pal(4, 1, PixelFormat::rgb8);
  ASSERT_EQ(reader.read(dir.file("pal.png").c_str(), pal.view), PgmFault::none) << reader.error();
  EXPECT_EQ(pal.bytes, (std::vector<std::uint8_t>{255, 0, 0, 0, 255, 0, 0, 0, 255, 0, 255, 0}));
}

TEST(Png, DamagedFilesNameTheFileAndTheReason) {
  test::TempDir dir;
  Buffer src(64, 48, PixelFormat::rgb8);
  fill_pattern(src, 4);
  const std::string good = dir.file("good.png");
  write_png(good, src.view);
  const auto size = std::filesystem::file_size(good);
  PngReader reader;
  Buffer into(64, 48, PixelFormat::rgb8);
  const auto expect = [&](const std::string& path, PgmFault fault, const std::string& reason) {
    EXPECT_EQ(reader.read(path.c_str(), into.view), fault) << reader.error();
    EXPECT_EQ(std::string(reader.error()), path + ": " + reason);
  };

  expect(dir.file("none.png"), PgmFault::missing, "missing (no such file)");
  std::ofstream(dir.file("empty.png")).close();
  expect(dir.file("empty.png"), PgmFault::truncated, "truncated: the file is empty");
  std::ofstream(dir.file("text.png")) << "P5\n2 2\n255\nabcd";
  expect(dir.file("text.png"), PgmFault::bad_header, "bad header: not a PNG (no PNG signature)");

  // Cut in the middle of the pixel data, and in the header.
  std::filesystem::copy_file(good, dir.file("half.png"));
  std::filesystem::resize_file(dir.file("half.png"), size / 2);
  EXPECT_EQ(reader.read(dir.file("half.png").c_str(), into.view), PgmFault::truncated);
  EXPECT_NE(std::string(reader.error()).find(": truncated: the file ends after "), std::string::npos) << reader.error();
  EXPECT_NE(std::string(reader.error()).find(" of 48"), std::string::npos) << reader.error();
  std::filesystem::copy_file(good, dir.file("head.png"));
  std::filesystem::resize_file(dir.file("head.png"), 20);
  expect(dir.file("head.png"), PgmFault::truncated, "truncated: the file ends in the header, after 20 bytes");
  // The last bytes (IEND) missing: the file is not whole.
  std::filesystem::copy_file(good, dir.file("tail.png"));
  std::filesystem::resize_file(dir.file("tail.png"), size - 6);
  EXPECT_EQ(reader.read(dir.file("tail.png").c_str(), into.view), PgmFault::truncated) << reader.error();

  // A flipped byte in the compressed data: the chunk's CRC no longer matches.
  std::string bytes;
  {
    std::ifstream in(good, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    bytes = s.str();
  }
  const std::size_t idat = bytes.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  std::string flipped = bytes;
  flipped[idat + 40] = static_cast<char>(flipped[idat + 40] ^ 0x55);
  std::ofstream(dir.file("flip.png"), std::ios::binary) << flipped;
  EXPECT_EQ(reader.read(dir.file("flip.png").c_str(), into.view), PgmFault::corrupt) << reader.error();
  EXPECT_NE(std::string(reader.error()).find(": corrupt: "), std::string::npos) << reader.error();
  // A damaged header chunk (width byte changed, CRC not).
  std::string bad_ihdr = bytes;
  bad_ihdr[18] = static_cast<char>(bad_ihdr[18] ^ 0x01);
  std::ofstream(dir.file("ihdr.png"), std::ios::binary) << bad_ihdr;
  EXPECT_EQ(reader.read(dir.file("ihdr.png").c_str(), into.view), PgmFault::bad_header) << reader.error();

  // Another size, another kind, 16 bits.
  Buffer small(32, 48, PixelFormat::rgb8);
  EXPECT_EQ(reader.read(good.c_str(), small.view), PgmFault::wrong_size);
  EXPECT_EQ(std::string(reader.error()), good + ": wrong size: 64x48, expected 32x48");
  Buffer grey(64, 48);
  EXPECT_EQ(reader.read(good.c_str(), grey.view), PgmFault::wrong_depth);
  EXPECT_EQ(std::string(reader.error()), good + ": wrong depth: colour PNG, expected 8-bit grey frames");
  const std::vector<std::uint16_t> deep(4, 1000);
  write_with_format(dir.file("deep.png"), PNG_FORMAT_LINEAR_Y, 2, 2, deep.data());
  PgmHeader h;
  EXPECT_EQ(reader.probe(dir.file("deep.png").c_str(), h), PgmFault::wrong_depth);
  EXPECT_EQ(std::string(reader.error()),
            dir.file("deep.png") + ": wrong depth: 16-bit PNG; only 8-bit PNG frames are read (16-bit frames are PGM)");

  // After all that, the reader still reads a good file.
  ASSERT_EQ(reader.read(good.c_str(), into.view), PgmFault::none) << reader.error();
  EXPECT_EQ(into.bytes, src.bytes);
}

TEST(Png, ReadingAFrameAllocatesNothing) {
  test::TempDir dir;
  Buffer src(1280, 720, PixelFormat::rgb8);
  fill_pattern(src, 5);
  const std::string path = dir.file("f.png");
  write_png(path, src.view);
  std::filesystem::copy_file(path, dir.file("cut.png"));
  std::filesystem::resize_file(dir.file("cut.png"), std::filesystem::file_size(path) / 3);
  const std::string cut = dir.file("cut.png"), none = dir.file("none.png");
  Buffer into(1280, 720, PixelFormat::rgb8);
  PngReader reader;
  ASSERT_EQ(reader.read(path.c_str(), into.view), PgmFault::none) << reader.error();
  test::AllocationScope scope;
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(reader.read(path.c_str(), into.view), PgmFault::none);
    EXPECT_EQ(reader.read(cut.c_str(), into.view), PgmFault::truncated);
    EXPECT_EQ(reader.read(none.c_str(), into.view), PgmFault::missing);
  }
  EXPECT_EQ(scope.count(), 0u);
  EXPECT_EQ(into.bytes, src.bytes);
  // libpng's own memory came from the reader's arena (its allocator is the arena's).
  EXPECT_GT(reader.peak_arena_bytes(), 32u * 1024u);
  std::printf("PNG decode of a 1280x720 RGB frame: %zu bytes of arena at the peak\n", reader.peak_arena_bytes());
}

TEST(Png, WriteFailureLeavesNoFile) {
  test::TempDir dir;
  Buffer src(4, 4);
  EXPECT_THROW(write_png(dir.file("no/such/dir/a.png"), src.view), std::runtime_error);
  Buffer deep(4, 4, PixelFormat::mono16);
  EXPECT_THROW(write_png(dir.file("d.png"), deep.view), std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(dir.file("d.png")));
  EXPECT_FALSE(std::filesystem::exists(dir.file("d.png.tmp")));
}

TEST(Png, ExtensionTellsPngFrames) {
  EXPECT_TRUE(has_png_extension("a/000001.png"));
  EXPECT_TRUE(has_png_extension("X.PNG"));
  EXPECT_FALSE(has_png_extension("000001.pgm"));
  EXPECT_FALSE(has_png_extension("png"));
  EXPECT_FALSE(has_png_extension("a.apng"));
}

// A small PNG may claim a huge picture (a 389 kB mask once cost 400 MB): read whole, its
// header's size is bounded before anything is allocated, and the file is named.
TEST(Png, AWholePictureLargerThanTheBoundIsRefusedFromItsHeader) {
  test::TempDir dir;
  const int side = 7000;  // 49 million pixels of zeros: a few hundred kB compressed
  std::vector<std::uint8_t> zeros(static_cast<std::size_t>(side) * side, 0);
  const std::string path = dir.file("mask.png");
  write_png(path, ImageView{zeros.data(), side, side, side, PixelFormat::mono8, 8}, 9);
  zeros = {};
  EXPECT_LT(std::filesystem::file_size(path), 1u << 20);
  try {
    read_png_picture(path);
    ADD_FAILURE() << "decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), path + ": 7000x7000 pixels: more than 40000000; not decoded");
  }
}

}  // namespace
}  // namespace ccdlane
