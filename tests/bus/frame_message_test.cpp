// frame_t <-> image: pixels, stride, format, depth and gyro survive the round trip; a
// message that cannot hold the image it claims is refused with the reason.
#include "bus/frame_message.hpp"

#include <cstring>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

// A padded buffer (stride > row), as the frame pool's rows are, with distinct pixels.
struct PaddedImage {
  PaddedImage(int w, int h, PixelFormat format, int bits) {
    const int bpp = bytes_per_pixel(format);
    stride = w * bpp + 24;
    pixels.resize(static_cast<std::size_t>(stride) * static_cast<std::size_t>(h), 0xEE);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const auto v = static_cast<std::uint16_t>((x * 7 + y * 13) % (1 << bits));
        std::uint8_t* p = pixels.data() + y * stride + x * bpp;
        if (bpp == 1)
          *p = static_cast<std::uint8_t>(v);
        else
          std::memcpy(p, &v, 2);
      }
    view = ImageView{pixels.data(), w, h, stride, format, bits};
  }
  std::vector<std::uint8_t> pixels;
  std::ptrdiff_t stride = 0;
  ImageView view;
};

void expect_same_pixels(const ImageView& a, const ImageView& b) {
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  ASSERT_EQ(a.format, b.format);
  EXPECT_EQ(a.significant_bits, b.significant_bits);
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) ASSERT_EQ(a.at(x, y), b.at(x, y)) << x << "," << y;
}

TEST(FrameMessage, Mono8RoundTripsThroughEncodeAndDecode) {
  const PaddedImage image(37, 11, PixelFormat::mono8, 8);
  frame_t msg{};
  prepare_frame_message(msg, 37, 11, PixelFormat::mono8);
  const FrameRecord record{42, 1'400'000'000, 1'700'000'000'000'000, Gx1Angles{1.5, -2.25, 179.0}};
  ASSERT_TRUE(to_frame_message(image.view, record, msg));
  EXPECT_EQ(msg.row_stride, 37) << "rows are packed";
  EXPECT_EQ(msg.data_size, 37 * 11);

  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  ASSERT_EQ(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  frame_t back{};
  ASSERT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  ImageView decoded;
  ASSERT_EQ(frame_image(back, decoded), "");
  expect_same_pixels(image.view, decoded);
  const FrameRecord r = frame_record(back);
  EXPECT_EQ(r.sequence, 42u);
  EXPECT_EQ(r.t_ns, 1'400'000'000);
  EXPECT_EQ(r.utime, 1'700'000'000'000'000);
  ASSERT_TRUE(r.gyro.has_value());
  EXPECT_EQ(r.gyro->roll_deg, 1.5);
  EXPECT_EQ(r.gyro->pitch_deg, -2.25);
  EXPECT_EQ(r.gyro->yaw_deg, 179.0);
}

TEST(FrameMessage, Mono16KeepsSamplesAndDepthAndNoGyroStaysNone) {
  const PaddedImage image(20, 9, PixelFormat::mono16, 12);
  frame_t msg{};
  prepare_frame_message(msg, 20, 9, PixelFormat::mono16);
  ASSERT_TRUE(to_frame_message(image.view, {3, 5, 7, std::nullopt}, msg));
  EXPECT_EQ(msg.pixel_format, frame_t::PIXEL_FORMAT_MONO16);
  EXPECT_EQ(msg.row_stride, 40);
  EXPECT_EQ(msg.significant_bits, 12);
  ImageView decoded;
  ASSERT_EQ(frame_image(msg, decoded), "");
  expect_same_pixels(image.view, decoded);
  EXPECT_FALSE(frame_record(msg).gyro.has_value());
}

TEST(FrameMessage, ColourFramesKeepTheirBytesAndTheirOrder) {
  for (const PixelFormat format : {PixelFormat::rgb8, PixelFormat::bgr8}) {
    constexpr int w = 13, h = 5;
    std::vector<std::uint8_t> pixels(static_cast<std::size_t>((3 * w + 7) * h));
    for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i * 29 + 3);
    const ImageView image{pixels.data(), w, h, 3 * w + 7, format, 8};
    frame_t msg{};
    prepare_frame_message(msg, w, h, format);
    ASSERT_TRUE(to_frame_message(image, {1, 2, 3, std::nullopt}, msg));
    EXPECT_EQ(msg.pixel_format, format == PixelFormat::rgb8 ? frame_t::PIXEL_FORMAT_RGB8 : frame_t::PIXEL_FORMAT_BGR8);
    EXPECT_EQ(msg.row_stride, 3 * w);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
    ASSERT_EQ(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    frame_t back{};
    ASSERT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
    ImageView decoded;
    ASSERT_EQ(frame_image(back, decoded), "");
    EXPECT_EQ(decoded.format, format);
    for (int y = 0; y < h; ++y) EXPECT_EQ(std::memcmp(decoded.row(y), image.row(y), 3 * w), 0) << "row " << y;
  }
}

TEST(FrameMessage, TheVehicleAtTheFrameRoundTrips) {
  const PaddedImage image(8, 4, PixelFormat::mono8, 8);
  frame_t msg{};
  prepare_frame_message(msg, 8, 4, PixelFormat::mono8);
  FrameRecord record{1, 2, 3, std::nullopt};
  record.speed_kmh = 72.0;
  record.yaw_rate_radps = -0.01;
  record.indicator = TurnIndicator::right;
  ASSERT_TRUE(to_frame_message(image.view, record, msg));
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  ASSERT_EQ(msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  frame_t back{};
  ASSERT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const FrameRecord r = frame_record(back);
  EXPECT_EQ(r.speed_kmh, 72.0);
  EXPECT_EQ(r.yaw_rate_radps, -0.01);
  EXPECT_EQ(r.indicator, TurnIndicator::right);

  ASSERT_TRUE(to_frame_message(image.view, {1, 2, 3, std::nullopt}, msg));
  EXPECT_FALSE(frame_record(msg).speed_kmh) << "unknown stays unknown";
  EXPECT_FALSE(frame_record(msg).yaw_rate_radps);
  EXPECT_EQ(frame_record(msg).indicator, TurnIndicator::none);
  msg.turn_indicator = 9;  // a code this reader does not know
  EXPECT_EQ(frame_record(msg).indicator, TurnIndicator::none);
}

TEST(FrameMessage, AnImageOfAnotherSizeOrFormatIsRefused) {
  const PaddedImage image(20, 9, PixelFormat::mono8, 8);
  frame_t msg{};
  prepare_frame_message(msg, 20, 10, PixelFormat::mono8);
  msg.sequence = 77;
  EXPECT_FALSE(to_frame_message(image.view, {1, 2, 3, std::nullopt}, msg));
  EXPECT_EQ(msg.sequence, 77) << "unchanged";
  prepare_frame_message(msg, 20, 9, PixelFormat::mono16);
  EXPECT_FALSE(to_frame_message(image.view, {1, 2, 3, std::nullopt}, msg));
}

TEST(FrameMessage, AMessageThatCannotHoldItsImageSaysWhy) {
  const PaddedImage image(8, 4, PixelFormat::mono8, 8);
  frame_t good{};
  prepare_frame_message(good, 8, 4, PixelFormat::mono8);
  ASSERT_TRUE(to_frame_message(image.view, {12, 0, 0, std::nullopt}, good));
  ImageView out;

  frame_t m = good;
  m.data_size = 31;
  m.data.resize(31);
  EXPECT_EQ(frame_image(m, out), "frame 12: data_size 31 is not row_stride x height = 32");
  m = good;
  m.pixel_format = 7;
  EXPECT_EQ(frame_image(m, out), "frame 12: unknown pixel_format 7");
  m = good;
  m.row_stride = 7;
  EXPECT_EQ(frame_image(m, out), "frame 12: row_stride 7 is shorter than a row");
  m = good;
  m.height = 0;
  EXPECT_EQ(frame_image(m, out), "frame 12: impossible size 8x0");
  m = good;
  m.significant_bits = 12;
  EXPECT_EQ(frame_image(m, out), "frame 12: significant_bits 12 is impossible for its pixel_format");
}

TEST(FrameMessage, FillingAPreparedMessageDoesNotReallocate) {
  const PaddedImage image(64, 48, PixelFormat::mono8, 8);
  frame_t msg{};
  prepare_frame_message(msg, 64, 48, PixelFormat::mono8);
  const std::uint8_t* storage = msg.data.data();
  for (std::uint64_t k = 0; k < 3; ++k) ASSERT_TRUE(to_frame_message(image.view, {k, 0, 0, std::nullopt}, msg));
  EXPECT_EQ(msg.data.data(), storage);
}

}  // namespace
}  // namespace ccdlane
