// Wire-to-mono conversions against hand-built frames with padding, both byte orders and
// YUYV, plus the refusals (short source, wrong destination format).
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
  EXPECT_TRUE(convert_frame(src.data(), 5, src.size(), WirePixels::mono8, {dst.data(), 3, 2, 3, PixelFormat::mono8, 8}));
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
  const std::vector<std::uint8_t> src{10, 128, 11, 129, 12, 130, 13, 131, 0, 0,
                                      20, 1,   21, 2,   22, 3,   23, 4};
  std::vector<std::uint8_t> dst(8);
  ASSERT_TRUE(convert_frame(src.data(), 10, src.size(), WirePixels::yuyv, {dst.data(), 4, 2, 4, PixelFormat::mono8, 8}));
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

TEST(PixelConversion, FormatsMapToTheirMonoCounterparts) {
  EXPECT_EQ(pixel_format_of(WirePixels::yuyv), PixelFormat::mono8);
  EXPECT_EQ(pixel_format_of(WirePixels::mono16_be), PixelFormat::mono16);
  EXPECT_EQ(wire_bytes_per_pixel(WirePixels::yuyv), 2);
}

}  // namespace
}  // namespace ccdlane
