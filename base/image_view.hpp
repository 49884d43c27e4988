// A non-owning view of an image (mono or packed colour): what camera drivers and frame
// files produce and what detection consumes. Pixels are never copied to pass a frame along.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ccdlane {

enum class PixelFormat : std::uint8_t {
  mono8,   // one byte per pixel
  mono16,  // one native-endian uint16 per pixel (PGM files are big-endian on disk)
  rgb8,    // three bytes per pixel: red, green, blue
  bgr8,    // three bytes per pixel: blue, green, red (OpenCV's and many cameras' order)
};

constexpr int bytes_per_pixel(PixelFormat f) {
  return f == PixelFormat::mono16 ? 2 : (f == PixelFormat::rgb8 || f == PixelFormat::bgr8) ? 3 : 1;
}
constexpr bool is_colour(PixelFormat f) { return f == PixelFormat::rgb8 || f == PixelFormat::bgr8; }

// Rec. 601 luma of 8-bit RGB in integer arithmetic (weights 77, 150, 29 of 256).
constexpr std::uint8_t luma8(unsigned r, unsigned g, unsigned b) {
  return static_cast<std::uint8_t>((77 * r + 150 * g + 29 * b + 128) >> 8);
}

struct ImageView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride_bytes = 0;  // from one row's start to the next
  PixelFormat format = PixelFormat::mono8;
  int significant_bits = 8;  // 8 for mono8 and colour; up to 16 for mono16 (PGM maxval, sensor depth)

  const std::uint8_t* row(int y) const { return data + y * stride_bytes; }
  // Pixel value at 0-based (x, y), widened (the luma of a colour pixel); callers on hot
  // paths index rows directly.
  std::uint16_t at(int x, int y) const {
    switch (format) {
      case PixelFormat::mono8: return row(y)[x];
      case PixelFormat::mono16: return reinterpret_cast<const std::uint16_t*>(row(y))[x];
      case PixelFormat::rgb8: {
        const std::uint8_t* p = row(y) + 3 * x;
        return luma8(p[0], p[1], p[2]);
      }
      case PixelFormat::bgr8: {
        const std::uint8_t* p = row(y) + 3 * x;
        return luma8(p[2], p[1], p[0]);
      }
    }
    return 0;
  }
  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
};

// The mutable counterpart, for renderers and decoders writing into a fixed buffer.
struct MutableImageView {
  std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride_bytes = 0;
  PixelFormat format = PixelFormat::mono8;
  int significant_bits = 8;

  std::uint8_t* row(int y) const { return data + y * stride_bytes; }
  operator ImageView() const { return {data, width, height, stride_bytes, format, significant_bits}; }
};

}  // namespace ccdlane
