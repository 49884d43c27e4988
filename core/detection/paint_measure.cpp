// The lane-paint measure, per row and per pixel, for each pixel format.
#include "core/detection/paint_measure.hpp"

#include <cstring>

namespace ccdlane {

float paint_measure_levels_per_grey(const ImageView& image) {
  if (image.format != PixelFormat::mono16) return 1.0f;
  return static_cast<float>((1 << std::clamp(image.significant_bits, 9, 16)) - 1) / 255.0f;
}

void paint_measure_row(const ImageView& image, int y, int x0, int x1, std::uint16_t* out) {
  const std::uint8_t* row = image.row(y);
  switch (image.format) {
    case PixelFormat::mono8:
      for (int x = x0; x < x1; ++x) out[x] = row[x];
      return;
    case PixelFormat::mono16: std::memcpy(out + x0, row + 2 * x0, 2 * static_cast<std::size_t>(x1 - x0)); return;
    case PixelFormat::rgb8:
      for (int x = x0; x < x1; ++x) {
        const std::uint8_t* p = row + 3 * x;
        out[x] = static_cast<std::uint16_t>(paint_measure8(p[0], p[1], p[2]));
      }
      return;
    case PixelFormat::bgr8:
      for (int x = x0; x < x1; ++x) {
        const std::uint8_t* p = row + 3 * x;
        out[x] = static_cast<std::uint16_t>(paint_measure8(p[2], p[1], p[0]));
      }
      return;
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

int paint_measure_at(const ImageView& image, int x, int y) {
  const std::uint8_t* p = image.row(y) + static_cast<std::ptrdiff_t>(bytes_per_pixel(image.format)) * x;
  switch (image.format) {
    case PixelFormat::rgb8: return paint_measure8(p[0], p[1], p[2]);
    case PixelFormat::bgr8: return paint_measure8(p[2], p[1], p[0]);
    default: return image.at(x, y);
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
