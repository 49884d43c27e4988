// The lane-paint measure detection scans: one value per pixel in which white and yellow
// paint are both bright against asphalt and concrete. It is computed only where the
// scanner looks, one row at a time into the caller's buffer; never a whole-frame copy.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "base/image_view.hpp"

namespace ccdlane {

// How much the weaker of red and green stands above blue: high for yellow paint, near 0
// for white paint, grey asphalt and concrete (whose slight tint is below the noise),
// 0 for blue sky and shade, red cars and green leaves (which lack red or green).
constexpr int yellowness8(int r, int g, int b) { return std::max(0, std::min(r, g) - b); }

// Colour pixels: luma plus yellowness, 0..510 on the 8-bit scale. In grey, yellow paint
// on light concrete nearly vanishes (its luma is the concrete's); its yellowness puts it
// back as far above the road as white paint is.
constexpr int paint_measure8(int r, int g, int b) {
  return luma8(static_cast<unsigned>(r), static_cast<unsigned>(g), static_cast<unsigned>(b)) + yellowness8(r, g, b);
}

// The measure of grey frames is the pixel value itself (mono16 in its own levels), so
// grey detection is what it always was. This is how many measure levels one 8-bit grey
// level is: 1 for mono8 and colour, (2^bits - 1) / 255 for mono16.
float paint_measure_levels_per_grey(const ImageView& image);

// The measure of pixels x0..x1-1 of 0-based row y, into out[x0 .. x1).
void paint_measure_row(const ImageView& image, int y, int x0, int x1, std::uint16_t* out);

// The yellowness8 of one 0-based pixel; 0 for grey frames.
int paint_yellowness_at(const ImageView& image, int x, int y);

// The measure of one 0-based pixel. Inline: dot tests and gradients read it pixel by
// pixel, and a call per pixel was about 6 % of a TuSimple still's detection time.
[[gnu::always_inline]] inline int paint_measure_at(const ImageView& image, int x, int y) {
  const std::uint8_t* p = image.row(y) + static_cast<std::ptrdiff_t>(bytes_per_pixel(image.format)) * x;
  switch (image.format) {
    case PixelFormat::rgb8: return paint_measure8(p[0], p[1], p[2]);
    case PixelFormat::bgr8: return paint_measure8(p[2], p[1], p[0]);
    default: return image.at(x, y);
  }
}

// For tools, not the per-frame path: the measure of the whole frame as a mono8 picture
// (out: same size, mono8; mono16 scaled to 8 bits, the colour measure clipped at 255),
// so that a person sees what detection saw.
void render_paint_measure(const ImageView& image, const MutableImageView& out);

}  // namespace ccdlane
