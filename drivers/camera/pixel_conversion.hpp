// Converting what a camera puts on the wire (mono, YUYV/UYVY, RGB24/BGR24, 8-bit Bayer)
// into the mono8, mono16 or rgb8 buffers of the frame pool. Allocation-free; used on the
// capture path.
#pragma once

#include <cstddef>
#include <cstdint>

#include "base/image_view.hpp"

namespace ccdlane {

enum class WirePixels : std::uint8_t {
  mono8,       // V4L2 GREY, GenICam Mono8
  mono16_le,   // V4L2 Y16/Y12/Y10, GenICam Mono16/Mono12/Mono10 (unpacked, little endian)
  mono16_be,   // V4L2 Y16_BE, PGM files
  yuyv,        // V4L2 YUYV 4:2:2: Y0 U Y1 V per pixel pair
  uyvy,        // V4L2 UYVY 4:2:2: U Y0 V Y1 per pixel pair
  rgb24,       // V4L2 RGB24, GenICam RGB8
  bgr24,       // V4L2 BGR24, GenICam BGR8
  bayer_rggb,  // 8-bit Bayer mosaics, named by the colours of the top-left 2x2 cell
  bayer_bggr,
  bayer_grbg,
  bayer_gbrg,
};

constexpr int wire_bytes_per_pixel(WirePixels w) {
  switch (w) {
    case WirePixels::mono16_le:
    case WirePixels::mono16_be:
    case WirePixels::yuyv:
    case WirePixels::uyvy: return 2;
    case WirePixels::rgb24:
    case WirePixels::bgr24: return 3;
    default: return 1;
  }
}

constexpr bool is_colour_wire(WirePixels w) {
  return w != WirePixels::mono8 && w != WirePixels::mono16_le && w != WirePixels::mono16_be;
}

// The format a wire layout naturally converts into: its colour when it has one.
constexpr PixelFormat pixel_format_of(WirePixels w) {
  if (w == WirePixels::mono16_le || w == WirePixels::mono16_be) return PixelFormat::mono16;
  return is_colour_wire(w) ? PixelFormat::rgb8 : PixelFormat::mono8;
}

// Whether convert_frame turns `w` into `f`: every layout into its own format, and 4:2:2
// into mono8 too (its Y plane, for a grey pipeline on a colour webcam).
constexpr bool converts_to(WirePixels w, PixelFormat f) {
  return f == pixel_format_of(w) || (f == PixelFormat::mono8 && (w == WirePixels::yuyv || w == WirePixels::uyvy));
}

// Copies (converting) a dst.width x dst.height frame from `src`, whose rows are
// `src_stride` bytes apart and which holds `src_bytes` bytes. False, with `dst`
// untouched, when `src` is too short or converts_to(wire, dst.format) is false.
//   4:2:2 -> rgb8: BT.601 limited range (Y 16..235), as UVC cameras send it.
//   Bayer -> rgb8: each pixel takes the red, the blue and the mean of the two greens of
//   the 2x2 cell starting at it (at the last row/column: the cell ending at it). Bayer
//   frames need even widths and heights of at least 2, 4:2:2 -> rgb8 an even width.
[[nodiscard]] bool convert_frame(const std::uint8_t* src, std::ptrdiff_t src_stride, std::size_t src_bytes,
                                 WirePixels wire, const MutableImageView& dst);

}  // namespace ccdlane
