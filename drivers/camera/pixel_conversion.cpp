// Row-by-row conversions; the compiler vectorises the inner loops.
#include "drivers/camera/pixel_conversion.hpp"

#include <bit>
#include <cstring>

namespace ccdlane {
namespace {

void copy_rows(const std::uint8_t* src, std::ptrdiff_t src_stride, const MutableImageView& dst, std::size_t row_bytes) {
  for (int y = 0; y < dst.height; ++y) std::memcpy(dst.row(y), src + src_stride * y, row_bytes);
}

void swap_rows16(const std::uint8_t* src, std::ptrdiff_t src_stride, const MutableImageView& dst) {
  for (int y = 0; y < dst.height; ++y) {
    const std::uint8_t* s = src + src_stride * y;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x < dst.width; ++x) {
      d[2 * x] = s[2 * x + 1];
      d[2 * x + 1] = s[2 * x];
    }
  }
}

void y_plane_of_yuyv(const std::uint8_t* src, std::ptrdiff_t src_stride, const MutableImageView& dst) {
  for (int y = 0; y < dst.height; ++y) {
    const std::uint8_t* s = src + src_stride * y;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x < dst.width; ++x) d[x] = s[2 * x];
  }
}

}  // namespace

bool convert_frame(const std::uint8_t* src, std::ptrdiff_t src_stride, std::size_t src_bytes, WirePixels wire,
                   const MutableImageView& dst) {
  if (src == nullptr || dst.data == nullptr || dst.width <= 0 || dst.height <= 0) return false;
  if (dst.format != pixel_format_of(wire)) return false;
  const auto src_row = static_cast<std::ptrdiff_t>(dst.width) * wire_bytes_per_pixel(wire);
  if (src_stride < src_row) return false;
  if (src_bytes < static_cast<std::size_t>(src_stride * (dst.height - 1) + src_row)) return false;
  const auto dst_row = static_cast<std::size_t>(dst.width) * static_cast<std::size_t>(bytes_per_pixel(dst.format));
  switch (wire) {
    case WirePixels::mono8:
      copy_rows(src, src_stride, dst, dst_row);
      return true;
    case WirePixels::mono16_le:
      if constexpr (std::endian::native == std::endian::little) copy_rows(src, src_stride, dst, dst_row);
      else swap_rows16(src, src_stride, dst);
      return true;
    case WirePixels::mono16_be:
      if constexpr (std::endian::native == std::endian::big) copy_rows(src, src_stride, dst, dst_row);
      else swap_rows16(src, src_stride, dst);
      return true;
    case WirePixels::yuyv:
      y_plane_of_yuyv(src, src_stride, dst);
      return true;
  }
  return false;
}

}  // namespace ccdlane
