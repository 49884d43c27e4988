// JPEG frames: a picture encoded here (libjpeg, quality 100) decodes to its pixels within
// JPEG's rounding, in colour and as grey; the real TuSimple pictures' size and format;
// every kind of bad file with its reason, the size checked before decoding.
#include "drivers/frames/jpeg.hpp"

#include <jpeglib.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "tests/support/run_process.hpp"

namespace ccdlane {
namespace {

// A smooth colour gradient as a quality-100 JPEG (no chroma subsampling): what it holds
// is known to a grey level or two.
std::vector<std::uint8_t> gradient(int w, int h) {
  std::vector<std::uint8_t> rgb(static_cast<std::size_t>(w * h * 3));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &rgb[static_cast<std::size_t>((y * w + x) * 3)];
      p[0] = static_cast<std::uint8_t>(40 + x * 150 / w);
      p[1] = static_cast<std::uint8_t>(60 + y * 150 / h);
      p[2] = static_cast<std::uint8_t>(90);
    }
  return rgb;
}

void write_jpeg(const std::string& path, const std::vector<std::uint8_t>& rgb, int w, int h) {
  jpeg_compress_struct info{};
  jpeg_error_mgr err{};
  info.err = jpeg_std_error(&err);
  jpeg_create_compress(&info);
  FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  jpeg_stdio_dest(&info, f);
  info.image_width = static_cast<JDIMENSION>(w);
  info.image_height = static_cast<JDIMENSION>(h);
  info.input_components = 3;
  info.in_color_space = JCS_RGB;
  jpeg_set_defaults(&info);
  jpeg_set_quality(&info, 100, TRUE);
  for (int c = 0; c < 3; ++c) info.comp_info[c].h_samp_factor = info.comp_info[c].v_samp_factor = 1;
  jpeg_start_compress(&info, TRUE);
  while (info.next_scanline < info.image_height) {
    JSAMPROW row = const_cast<std::uint8_t*>(&rgb[static_cast<std::size_t>(info.next_scanline) * w * 3]);
    jpeg_write_scanlines(&info, &row, 1);
  }
  jpeg_finish_compress(&info);
  jpeg_destroy_compress(&info);
  std::fclose(f);
}

std::string bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void write_bytes(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

TEST(JpegReader, DecodesColourAndGreyWithinRounding) {
  test::TempDir dir;
  const int w = 64, h = 48;
  const std::vector<std::uint8_t> rgb = gradient(w, h);
  const std::string path = dir.path() + "/g.jpg";
  write_jpeg(path, rgb, w, h);
  JpegReader reader;
  PgmHeader header;
  ASSERT_EQ(reader.probe(path.c_str(), header), PgmFault::none) << reader.error();
  EXPECT_EQ(header.width, w);
  EXPECT_EQ(header.height, h);
  EXPECT_EQ(header.channels, 3);

  std::vector<std::uint8_t> colour(static_cast<std::size_t>(w * h * 3));
  ASSERT_EQ(reader.read(path.c_str(), {colour.data(), w, h, w * 3, PixelFormat::rgb8, 8}), PgmFault::none);
  int worst = 0;
  for (std::size_t i = 0; i < rgb.size(); ++i) worst = std::max(worst, std::abs(colour[i] - rgb[i]));
  EXPECT_LE(worst, 3) << "quality 100 without subsampling: DCT rounding only";

  std::vector<std::uint8_t> grey(static_cast<std::size_t>(w * h));
  ASSERT_EQ(reader.read(path.c_str(), {grey.data(), w, h, w, PixelFormat::mono8, 8}), PgmFault::none);
  for (std::size_t i = 0; i < grey.size(); ++i) {
    const double luma = 0.299 * rgb[3 * i] + 0.587 * rgb[3 * i + 1] + 0.114 * rgb[3 * i + 2];
    ASSERT_NEAR(grey[i], luma, 3.0) << "pixel " << i;
  }
}

TEST(JpegReader, TheTuSimpleStillsAreColourFramesOfTheirCamera) {
  JpegReader reader;
  const std::string path = std::string(CCDLANE_TEST_DATA_DIR) + "/real/tusimple/images/0000.jpg";
  PgmHeader header;
  ASSERT_EQ(reader.probe(path.c_str(), header), PgmFault::none) << reader.error();
  EXPECT_EQ(header.width, 1280);
  EXPECT_EQ(header.height, 720);
  EXPECT_EQ(header.channels, 3);
  EXPECT_EQ(header.format(), PixelFormat::rgb8);
}

TEST(JpegReader, BadFilesSayWhy) {
  test::TempDir dir;
  const int w = 64, h = 48;
  const std::string good = dir.path() + "/g.jpg";
  write_jpeg(good, gradient(w, h), w, h);
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w * h * 3));
  const MutableImageView frame{px.data(), w, h, w * 3, PixelFormat::rgb8, 8};
  JpegReader reader;
  auto fault = [&](const std::string& path, const MutableImageView& into) { return reader.read(path.c_str(), into); };

  EXPECT_EQ(fault(dir.path() + "/none.jpg", frame), PgmFault::missing);
  write_bytes(dir.path() + "/empty.jpg", "");
  EXPECT_EQ(fault(dir.path() + "/empty.jpg", frame), PgmFault::truncated);
  write_bytes(dir.path() + "/text.jpg", "not a picture\n");
  EXPECT_EQ(fault(dir.path() + "/text.jpg", frame), PgmFault::bad_header);
  EXPECT_NE(std::string(reader.error()).find("text.jpg: bad header: not a JPEG"), std::string::npos) << reader.error();

  const std::string bytes = bytes_of(good);
  write_bytes(dir.path() + "/head.jpg", bytes.substr(0, 40));  // the header cut off
  EXPECT_EQ(fault(dir.path() + "/head.jpg", frame), PgmFault::bad_header) << reader.error();
  write_bytes(dir.path() + "/cut.jpg", bytes.substr(0, bytes.size() * 2 / 3));  // the data cut off
  EXPECT_EQ(fault(dir.path() + "/cut.jpg", frame), PgmFault::truncated) << reader.error();

  std::vector<std::uint8_t> small(static_cast<std::size_t>(32 * 24 * 3));
  EXPECT_EQ(fault(good, {small.data(), 32, 24, 32 * 3, PixelFormat::rgb8, 8}), PgmFault::wrong_size);
  EXPECT_NE(std::string(reader.error()).find("wrong size: 64x48, expected 32x24"), std::string::npos) << reader.error();
}

}  // namespace
}  // namespace ccdlane
