// Converting what a camera puts on the wire (Mono8, 16-bit little/big endian, YUYV) into
// the mono buffers of the frame pool. Allocation-free; used on the capture path.
#pragma once

#include <cstddef>
#include <cstdint>

#include "base/image_view.hpp"

namespace ccdlane {

enum class WirePixels : std::uint8_t {
  mono8,      // V4L2 GREY, GenICam Mono8
  mono16_le,  // V4L2 Y16/Y12/Y10, GenICam Mono16/Mono12/Mono10 (unpacked, little endian)
  mono16_be,  // V4L2 Y16_BE, PGM files
  yuyv,       // V4L2 YUYV 4:2:2: the Y plane is every other byte
};

constexpr int wire_bytes_per_pixel(WirePixels w) { return w == WirePixels::mono8 ? 1 : 2; }

// The mono format a wire layout converts into.
constexpr PixelFormat pixel_format_of(WirePixels w) {
  return w == WirePixels::mono16_le || w == WirePixels::mono16_be ? PixelFormat::mono16 : PixelFormat::mono8;
}

// Copies (converting) a dst.width x dst.height frame from `src`, whose rows are
// `src_stride` bytes apart and which holds `src_bytes` bytes. False, with `dst`
// untouched, when `src` is too short or `dst` has the wrong format for `wire`.
[[nodiscard]] bool convert_frame(const std::uint8_t* src, std::ptrdiff_t src_stride, std::size_t src_bytes,
                                 WirePixels wire, const MutableImageView& dst);

}  // namespace ccdlane
