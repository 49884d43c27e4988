// The lane-paint measure, per row and per pixel, for each pixel format.
#include "core/detection/paint_measure.hpp"

#include <cstring>

#include "core/detection/pixel_loop_clones.hpp"

namespace ccdlane {

float paint_measure_levels_per_grey(const ImageView& image) {
  if (image.format != PixelFormat::mono16) return 1.0f;
  return static_cast<float>((1 << std::clamp(image.significant_bits, 9, 16)) - 1) / 255.0f;
}

namespace {

// Three-byte pixels to their measure: built for the CPU's best target
// (pixel_loop_clones.hpp), where x86-64's baseline alone left the loop scalar, a third
// of a TuSimple still's detection time. The pointers are restrict: a byte pointer may
// alias anything, and the compiler must know the stores do not change the pixels still
// to be read.
CCDLANE_PIXEL_LOOP_CLONES
void rgb_row(const std::uint8_t* __restrict row, int n, std::uint16_t* __restrict out) {
  for (int x = 0; x < n; ++x)
    out[x] = static_cast<std::uint16_t>(paint_measure8(row[3 * x], row[3 * x + 1], row[3 * x + 2]));
}

CCDLANE_PIXEL_LOOP_CLONES
void bgr_row(const std::uint8_t* __restrict row, int n, std::uint16_t* __restrict out) {
  for (int x = 0; x < n; ++x)
    out[x] = static_cast<std::uint16_t>(paint_measure8(row[3 * x + 2], row[3 * x + 1], row[3 * x]));
}

}  // namespace

void paint_measure_row(const ImageView& image, int y, int x0, int x1, std::uint16_t* out) {
  const std::uint8_t* row = image.row(y);
  switch (image.format) {
    case PixelFormat::mono8:
      for (int x = x0; x < x1; ++x) out[x] = row[x];
      return;
    case PixelFormat::mono16: std::memcpy(out + x0, row + 2 * x0, 2 * static_cast<std::size_t>(x1 - x0)); return;
    case PixelFormat::rgb8: rgb_row(row + 3 * x0, x1 - x0, out + x0); return;
    case PixelFormat::bgr8: bgr_row(row + 3 * x0, x1 - x0, out + x0); return;
  }
}

int paint_yellowness_at(const ImageView& image, int x, int y) {
  const std::uint8_t* p = image.row(y) + static_cast<std::ptrdiff_t>(bytes_per_pixel(image.format)) * x;
  switch (image.format) {
    case PixelFormat::rgb8: return yellowness8(p[0], p[1], p[2]);
    case PixelFormat::bgr8: return yellowness8(p[2], p[1], p[0]);
    default: return 0;
  }
}

void render_paint_measure(const ImageView& image, const MutableImageView& out) {
  const int shift = image.format == PixelFormat::mono16 ? std::max(0, image.significant_bits - 8) : 0;
  for (int y = 0; y < std::min(image.height, out.height); ++y) {
    std::uint8_t* dst = out.row(y);
    for (int x = 0; x < std::min(image.width, out.width); ++x)
      dst[x] = static_cast<std::uint8_t>(std::min(255, paint_measure_at(image, x, y) >> shift));
  }
}

}  // namespace ccdlane
