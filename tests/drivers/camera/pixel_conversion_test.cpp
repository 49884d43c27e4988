// Wire-to-pool conversions against hand-built frames with padding, both byte orders,
// 4:2:2 (grey and colour), RGB/BGR and the four Bayer mosaics with pixels computed by
// hand, plus the refusals (short source, wrong destination format).
#include "drivers/camera/pixel_conversion.hpp"

#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(PixelConversion, Mono8CopiesRowsAndSkipsBothPaddings) {
  // 3x2 source with stride 5 (2 padding bytes), destination stride 4.
  const std::vector<std::uint8_t> src{1, 2, 3, 99, 99, 4, 5, 6, 99, 99};
  std::vector<std::uint8_t> dst(8, 0xee);
  const MutableImageView out{dst.data(), 3, 2, 4, PixelFormat::mono8, 8};
  ASSERT_TRUE(convert_frame(src.data(), 5, src.size(), WirePixels::mono8, out));
  EXPECT_EQ(dst, (std::vector<std::uint8_t>{1, 2, 3, 0xee, 4, 5, 6, 0xee}));
}

TEST(PixelConversion, LastRowNeedsNoPadding) {
  const std::vector<std::uint8_t> src{1, 2, 3, 99, 99, 4, 5, 6};  // 8 bytes: enough
  std::vector<std::uint8_t> dst(6);
  EXPECT_TRUE(
      convert_frame(src.data(), 5, src.size(), WirePixels::mono8, {dst.data(), 3, 2, 3, PixelFormat::mono8, 8}));
  EXPECT_FALSE(convert_frame(src.data(), 5, 7, WirePixels::mono8, {dst.data(), 3, 2, 3, PixelFormat::mono8, 8}));
}

TEST(PixelConversion, Mono16LittleAndBigEndianGiveTheSameValues) {
  const std::vector<std::uint8_t> le{0x34, 0x12, 0xff, 0x0f, 0x01, 0x00, 0x00, 0x80};
  const std::vector<std::uint8_t> be{0x12, 0x34, 0x0f, 0xff, 0x00, 0x01, 0x80, 0x00};
  for (auto [src, wire] : {std::pair{&le, WirePixels::mono16_le}, std::pair{&be, WirePixels::mono16_be}}) {
    std::vector<std::uint16_t> dst(4);
    const MutableImageView out{reinterpret_cast<std::uint8_t*>(dst.data()), 2, 2, 4, PixelFormat::mono16, 16};
    ASSERT_TRUE(convert_frame(src->data(), 4, src->size(), wire, out));
    EXPECT_EQ(dst, (std::vector<std::uint16_t>{0x1234, 0x0fff, 0x0001, 0x8000}));
  }
}

TEST(PixelConversion, YuyvKeepsTheLumaPlane) {
  // Y0 U Y1 V per pixel pair; 4x2 with a stride of 10 (2 padding bytes).
  const std::vector<std::uint8_t> src{10, 128, 11, 129, 12, 130, 13, 131, 0, 0, 20, 1, 21, 2, 22, 3, 23, 4};
  std::vector<std::uint8_t> dst(8);
  ASSERT_TRUE(
      convert_frame(src.data(), 10, src.size(), WirePixels::yuyv, {dst.data(), 4, 2, 4, PixelFormat::mono8, 8}));
  EXPECT_EQ(dst, (std::vector<std::uint8_t>{10, 11, 12, 13, 20, 21, 22, 23}));
}

TEST(PixelConversion, RefusesMismatchedFormatsAndStrides) {
  std::vector<std::uint8_t> src(64), dst(64);
  const MutableImageView mono8{dst.data(), 4, 2, 8, PixelFormat::mono8, 8};
  const MutableImageView mono16{dst.data(), 4, 2, 8, PixelFormat::mono16, 16};
  EXPECT_FALSE(convert_frame(src.data(), 8, src.size(), WirePixels::mono16_le, mono8));
  EXPECT_FALSE(convert_frame(src.data(), 8, src.size(), WirePixels::yuyv, mono16));
  EXPECT_FALSE(convert_frame(src.data(), 7, src.size(), WirePixels::yuyv, mono8));  // a YUYV row is 8 bytes
  EXPECT_FALSE(convert_frame(nullptr, 8, src.size(), WirePixels::mono8, mono8));
  EXPECT_EQ(dst, std::vector<std::uint8_t>(64));
}

TEST(PixelConversion, FormatsMapToTheirCounterparts) {
  EXPECT_EQ(pixel_format_of(WirePixels::yuyv), PixelFormat::rgb8);
  EXPECT_EQ(pixel_format_of(WirePixels::mono16_be), PixelFormat::mono16);
  EXPECT_EQ(pixel_format_of(WirePixels::bayer_gbrg), PixelFormat::rgb8);
  EXPECT_TRUE(converts_to(WirePixels::uyvy, PixelFormat::mono8));
  EXPECT_FALSE(converts_to(WirePixels::bayer_rggb, PixelFormat::mono8));
  EXPECT_FALSE(converts_to(WirePixels::mono8, PixelFormat::rgb8));
  EXPECT_EQ(wire_bytes_per_pixel(WirePixels::yuyv), 2);
  EXPECT_EQ(wire_bytes_per_pixel(WirePixels::bgr24), 3);
  EXPECT_EQ(wire_bytes_per_pixel(WirePixels::bayer_rggb), 1);
}

// BT.601 limited range by hand: C = 298 (Y - 16) + 128, D = U - 128, E = V - 128;
// R = (C + 409 E) >> 8, G = (C - 100 D - 208 E) >> 8, B = (C + 516 D) >> 8, clipped.
//   Y 81, U 90, V 240: C 19498 -> R 65306>>8 = 255, G 2>>8 = 0, B -110>>8 -> 0 (pure red)
//   Y 128, same U V:   C 33504 -> R 309 -> 255, G 14008>>8 = 54, B 13896>>8 = 54
//   Y 16, U V 128:     C 128 -> 0, 0, 0;  Y 235: C 65390 -> 255, 255, 255
TEST(PixelConversion, YuyvAndUyvyGiveBt601Colour) {
  const std::vector<std::uint8_t> yuyv{81, 90, 128, 240, 16, 128, 235, 128};
  const std::vector<std::uint8_t> uyvy{90, 81, 240, 128, 128, 16, 128, 235};
  const std::vector<std::uint8_t> expected{255, 0, 0, 255, 54, 54, 0, 0, 0, 255, 255, 255};
  for (auto [src, wire] : {std::pair{&yuyv, WirePixels::yuyv}, std::pair{&uyvy, WirePixels::uyvy}}) {
    std::vector<std::uint8_t> dst(12);
    ASSERT_TRUE(convert_frame(src->data(), 8, src->size(), wire, {dst.data(), 4, 1, 12, PixelFormat::rgb8, 8}));
    EXPECT_EQ(dst, expected);
  }
}

TEST(PixelConversion, UyvyGreyKeepsTheLumaPlane) {
  const std::vector<std::uint8_t> src{90, 81, 240, 128, 128, 16, 128, 235};
  std::vector<std::uint8_t> dst(4);
  ASSERT_TRUE(convert_frame(src.data(), 8, src.size(), WirePixels::uyvy, {dst.data(), 4, 1, 4, PixelFormat::mono8, 8}));
  EXPECT_EQ(dst, (std::vector<std::uint8_t>{81, 128, 16, 235}));
}

TEST(PixelConversion, Rgb24IsCopiedAndBgr24Swapped) {
  // 2x2, source stride 7 (one padding byte), destination stride 6.
  const std::vector<std::uint8_t> src{1, 2, 3, 4, 5, 6, 99, 7, 8, 9, 10, 11, 12};
  std::vector<std::uint8_t> dst(12);
  ASSERT_TRUE(convert_frame(src.data(), 7, src.size(), WirePixels::rgb24, {dst.data(), 2, 2, 6, PixelFormat::rgb8, 8}));
  EXPECT_EQ(dst, (std::vector<std::uint8_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12}));
  ASSERT_TRUE(convert_frame(src.data(), 7, src.size(), WirePixels::bgr24, {dst.data(), 2, 2, 6, PixelFormat::rgb8, 8}));
  EXPECT_EQ(dst, (std::vector<std::uint8_t>{3, 2, 1, 6, 5, 4, 9, 8, 7, 12, 11, 10}));
}

std::vector<std::uint8_t> rgb_at(const std::vector<std::uint8_t>& rgb, int width, int x, int y) {
  const auto i = static_cast<std::size_t>(3 * (y * width + x));
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

// RGGB 4x4:      R  G  R  G          10  20  30  40
//                G  B  G  B          50  60  70  80
//                R  G  R  G          90 100 110 120
//                G  B  G  B         130 140 150 160
// Each pixel takes R, B and the rounded mean of the two G of the 2x2 window at it:
//   (0,0): R 10, G (20+50+1)/2 = 35, B 60     (1,0): R 30, G (20+70+1)/2 = 45, B 60
//   (2,0): R 30, G (40+70+1)/2 = 55, B 80     (3,0): the window at (2,0) again
//   (0,1): R 90, G (50+100+1)/2 = 75, B 60    (1,1): R 110, G (70+100+1)/2 = 85, B 60
//   (0,3): the window at (0,2): R 90, G (100+130+1)/2 = 115, B 140
TEST(PixelConversion, BayerRggbTakesTheWindowAtEachPixel) {
  std::vector<std::uint8_t> src(16);
  for (int i = 0; i < 16; ++i) src[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(10 * (i + 1));
  std::vector<std::uint8_t> dst(48);
  ASSERT_TRUE(
      convert_frame(src.data(), 4, src.size(), WirePixels::bayer_rggb, {dst.data(), 4, 4, 12, PixelFormat::rgb8, 8}));
  using P = std::vector<std::uint8_t>;
  EXPECT_EQ(rgb_at(dst, 4, 0, 0), (P{10, 35, 60}));
  EXPECT_EQ(rgb_at(dst, 4, 1, 0), (P{30, 45, 60}));
  EXPECT_EQ(rgb_at(dst, 4, 2, 0), (P{30, 55, 80}));
  EXPECT_EQ(rgb_at(dst, 4, 3, 0), (P{30, 55, 80}));
  EXPECT_EQ(rgb_at(dst, 4, 0, 1), (P{90, 75, 60}));
  EXPECT_EQ(rgb_at(dst, 4, 1, 1), (P{110, 85, 60}));
  EXPECT_EQ(rgb_at(dst, 4, 0, 3), (P{90, 115, 140}));
}

TEST(PixelConversion, EachBayerMosaicPutsItsColoursWhereItsNameSays) {
  // One 2x2 cell 10 20 / 50 60 read as each mosaic: the named places give R and B, the
  // two others average into G.
  const std::vector<std::uint8_t> src{10, 20, 50, 60};
  using P = std::vector<std::uint8_t>;
  const std::pair<WirePixels, P> cases[] = {{WirePixels::bayer_rggb, P{10, 35, 60}},
                                            {WirePixels::bayer_bggr, P{60, 35, 10}},
                                            {WirePixels::bayer_grbg, P{20, 35, 50}},
                                            {WirePixels::bayer_gbrg, P{50, 35, 20}}};
  for (const auto& [wire, pixel] : cases) {
    std::vector<std::uint8_t> dst(12);
    ASSERT_TRUE(convert_frame(src.data(), 2, src.size(), wire, {dst.data(), 2, 2, 6, PixelFormat::rgb8, 8}));
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2; ++x) EXPECT_EQ(rgb_at(dst, 2, x, y), pixel) << static_cast<int>(wire);
  }
}

TEST(PixelConversion, AFlatColourSurvivesEveryBayerMosaic) {
  // A uniform (200, 120, 40) scene sampled through each mosaic must come back unchanged
  // at every pixel, edges included.
  constexpr int w = 6, h = 4;
  const std::uint8_t colour[3] = {200, 120, 40};
  const std::pair<WirePixels, const char*> mosaics[] = {{WirePixels::bayer_rggb, "RGGB"},
                                                        {WirePixels::bayer_bggr, "BGGR"},
                                                        {WirePixels::bayer_grbg, "GRBG"},
                                                        {WirePixels::bayer_gbrg, "GBRG"}};
  for (const auto& [wire, name] : mosaics) {
    std::vector<std::uint8_t> src(w * h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const char c = name[(y & 1) * 2 + (x & 1)];
        src[static_cast<std::size_t>(y * w + x)] = colour[c == 'R' ? 0 : c == 'G' ? 1 : 2];
      }
    std::vector<std::uint8_t> dst(3 * w * h);
    ASSERT_TRUE(convert_frame(src.data(), w, src.size(), wire, {dst.data(), w, h, 3 * w, PixelFormat::rgb8, 8}));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) EXPECT_EQ(rgb_at(dst, w, x, y), (std::vector<std::uint8_t>{200, 120, 40})) << name;
  }
}

TEST(PixelConversion, RefusesOddBayerAndOddColour422) {
  std::vector<std::uint8_t> src(64), dst(64);
  EXPECT_FALSE(
      convert_frame(src.data(), 3, src.size(), WirePixels::bayer_rggb, {dst.data(), 3, 2, 9, PixelFormat::rgb8, 8}));
  EXPECT_FALSE(convert_frame(src.data(), 6, src.size(), WirePixels::yuyv, {dst.data(), 3, 1, 9, PixelFormat::rgb8, 8}));
  EXPECT_FALSE(
      convert_frame(src.data(), 4, src.size(), WirePixels::bayer_rggb, {dst.data(), 4, 2, 4, PixelFormat::mono8, 8}));
  EXPECT_EQ(dst, std::vector<std::uint8_t>(64));
}

}  // namespace
}  // namespace ccdlane
