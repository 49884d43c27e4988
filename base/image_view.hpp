// A non-owning view of a mono image: what camera drivers and frame files produce and
// what detection consumes. Pixels are never copied to pass a frame along.
#pragma once

#include <cstddef>
#include <cstdint>

namespace ccdlane {

enum class PixelFormat : std::uint8_t {
  mono8,   // one byte per pixel
  mono16,  // one native-endian uint16 per pixel (PGM files are big-endian on disk)
};

constexpr int bytes_per_pixel(PixelFormat f) { return f == PixelFormat::mono16 ? 2 : 1; }

struct ImageView {
  const std::uint8_t* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride_bytes = 0;  // from one row's start to the next
  PixelFormat format = PixelFormat::mono8;
  int significant_bits = 8;  // 8 for mono8; up to 16 for mono16 (PGM maxval, sensor depth)

  const std::uint8_t* row(int y) const { return data + y * stride_bytes; }
  // Pixel value at 0-based (x, y), widened; callers on hot paths index rows directly.
  std::uint16_t at(int x, int y) const {
    return format == PixelFormat::mono8 ? row(y)[x] : reinterpret_cast<const std::uint16_t*>(row(y))[x];
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
