// Row-by-row conversions; the compiler vectorises the simple inner loops.
#include "drivers/camera/pixel_conversion.hpp"

#include <algorithm>
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

// `y_at` is the offset of Y0 within a 4-byte pixel pair: 0 for YUYV, 1 for UYVY.
void y_plane_of_422(const std::uint8_t* src, std::ptrdiff_t src_stride, int y_at, const MutableImageView& dst) {
  for (int y = 0; y < dst.height; ++y) {
    const std::uint8_t* s = src + src_stride * y + y_at;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x < dst.width; ++x) d[x] = s[2 * x];
  }
}

std::uint8_t clip8(int v) { return static_cast<std::uint8_t>(std::clamp(v, 0, 255)); }

// BT.601 limited range in 8.8 fixed point (the coefficients of Microsoft's and libyuv's
// integer YUV->RGB).
void rgb_of_yuv(int y, int u, int v, std::uint8_t* rgb) {
  const int c = 298 * (y - 16) + 128;
  const int d = u - 128;
  const int e = v - 128;
  rgb[0] = clip8((c + 409 * e) >> 8);
  rgb[1] = clip8((c - 100 * d - 208 * e) >> 8);
  rgb[2] = clip8((c + 516 * d) >> 8);
}

void rgb_of_422(const std::uint8_t* src, std::ptrdiff_t src_stride, bool uyvy, const MutableImageView& dst) {
  const int y0 = uyvy ? 1 : 0, u = uyvy ? 0 : 1, y1 = uyvy ? 3 : 2, v = uyvy ? 2 : 3;
  for (int y = 0; y < dst.height; ++y) {
    const std::uint8_t* s = src + src_stride * y;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x + 1 < dst.width; x += 2, s += 4, d += 6) {
      rgb_of_yuv(s[y0], s[u], s[v], d);
      rgb_of_yuv(s[y1], s[u], s[v], d + 3);
    }
  }
}

void rgb_of_bgr(const std::uint8_t* src, std::ptrdiff_t src_stride, const MutableImageView& dst) {
  for (int y = 0; y < dst.height; ++y) {
    const std::uint8_t* s = src + src_stride * y;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x < dst.width; ++x, s += 3, d += 3) {
      d[0] = s[2];
      d[1] = s[1];
      d[2] = s[0];
    }
  }
}

enum Cfa : std::uint8_t { red, green, blue };

// Colours of the top-left 2x2 cell, in the order (0,0), (1,0), (0,1), (1,1).
struct Mosaic {
  Cfa at[4];
};
Mosaic mosaic_of(WirePixels w) {
  switch (w) {
    case WirePixels::bayer_bggr: return {{blue, green, green, red}};
    case WirePixels::bayer_grbg: return {{green, red, blue, green}};
    case WirePixels::bayer_gbrg: return {{green, blue, red, green}};
    default: return {{red, green, green, blue}};
  }
}

// Every 2x2 window of a Bayer mosaic holds one red, one blue and two greens; which of its
// four places holds which depends only on the parities of the window's corner.
struct WindowPlaces {
  int red, blue, green_a, green_b;  // byte offsets from the window's top-left
};

void rgb_of_bayer(const std::uint8_t* src, std::ptrdiff_t src_stride, WirePixels wire, const MutableImageView& dst) {
  const Mosaic m = mosaic_of(wire);
  WindowPlaces places[4];  // by (corner y parity) * 2 + (corner x parity)
  for (int py = 0; py < 2; ++py)
    for (int px = 0; px < 2; ++px) {
      WindowPlaces& w = places[py * 2 + px];
      bool first_green = true;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int offset = static_cast<int>(dy * src_stride) + dx;
          switch (m.at[((py + dy) & 1) * 2 + ((px + dx) & 1)]) {
            case red: w.red = offset; break;
            case blue: w.blue = offset; break;
            case green:
              (first_green ? w.green_a : w.green_b) = offset;
              first_green = false;
              break;
          }
        }
    }
  for (int y = 0; y < dst.height; ++y) {
    const int y0 = std::min(y, dst.height - 2);
    const std::uint8_t* s = src + src_stride * y0;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x < dst.width; ++x, d += 3) {
      const int x0 = std::min(x, dst.width - 2);
      const WindowPlaces& w = places[(y0 & 1) * 2 + (x0 & 1)];
      const std::uint8_t* c = s + x0;
      d[0] = c[w.red];
      d[1] = static_cast<std::uint8_t>((c[w.green_a] + c[w.green_b] + 1) >> 1);
      d[2] = c[w.blue];
    }
  }
}

bool is_bayer(WirePixels w) {
  return w == WirePixels::bayer_rggb || w == WirePixels::bayer_bggr || w == WirePixels::bayer_grbg ||
         w == WirePixels::bayer_gbrg;
}

}  // namespace

bool convert_frame(const std::uint8_t* src, std::ptrdiff_t src_stride, std::size_t src_bytes, WirePixels wire,
                   const MutableImageView& dst) {
  if (src == nullptr || dst.data == nullptr || dst.width <= 0 || dst.height <= 0) return false;
  if (!converts_to(wire, dst.format)) return false;
  // A pair shares its chroma: colour from half a pair would read past the row.
  if ((wire == WirePixels::yuyv || wire == WirePixels::uyvy) && dst.format == PixelFormat::rgb8 && dst.width % 2)
    return false;
  if (is_bayer(wire) && (dst.width < 2 || dst.height < 2 || dst.width % 2 || dst.height % 2)) return false;
  const auto src_row = static_cast<std::ptrdiff_t>(dst.width) * wire_bytes_per_pixel(wire);
  if (src_stride < src_row) return false;
  if (src_bytes < static_cast<std::size_t>(src_stride * (dst.height - 1) + src_row)) return false;
  const auto dst_row = static_cast<std::size_t>(dst.width) * static_cast<std::size_t>(bytes_per_pixel(dst.format));
  const bool to_grey = dst.format == PixelFormat::mono8;
  switch (wire) {
    case WirePixels::mono8:
    case WirePixels::rgb24: copy_rows(src, src_stride, dst, dst_row); return true;
    case WirePixels::mono16_le:
      if constexpr (std::endian::native == std::endian::little)
        copy_rows(src, src_stride, dst, dst_row);
      else
        swap_rows16(src, src_stride, dst);
      return true;
    case WirePixels::mono16_be:
      if constexpr (std::endian::native == std::endian::big)
        copy_rows(src, src_stride, dst, dst_row);
      else
        swap_rows16(src, src_stride, dst);
      return true;
    case WirePixels::yuyv:
    case WirePixels::uyvy: {
      const bool uyvy = wire == WirePixels::uyvy;
      if (to_grey)
        y_plane_of_422(src, src_stride, uyvy ? 1 : 0, dst);
      else
        rgb_of_422(src, src_stride, uyvy, dst);
      return true;
    }
    case WirePixels::bgr24: rgb_of_bgr(src, src_stride, dst); return true;
    case WirePixels::bayer_rggb:
    case WirePixels::bayer_bggr:
    case WirePixels::bayer_grbg:
    case WirePixels::bayer_gbrg: rgb_of_bayer(src, src_stride, wire, dst); return true;
  }
  return false;
}

}  // namespace ccdlane
