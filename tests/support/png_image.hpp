// PNG pictures for tests: read a grey or RGB PNG into an owned image, write one out to
// look at (overlays, the paint-measure picture). The frame driver's PNG codec underneath.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/image_view.hpp"

namespace ccdlane::test {

struct PngImage {
  std::vector<std::uint8_t> pixels;
  int width = 0, height = 0;
  PixelFormat format = PixelFormat::mono8;  // mono8 or rgb8

  ImageView view() const {
    return {pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format), format, 8};
  }
  MutableImageView mutable_view() {
    return {pixels.data(), width, height, static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format), format, 8};
  }
};

// 8-bit grey becomes mono8, 8-bit RGB becomes rgb8 (alpha dropped, palettes expanded;
// 16-bit refused).
// Throws std::runtime_error naming the file when it cannot be read.
PngImage read_png(const std::string& path);

// Writes a mono8 or rgb8 image. Throws std::runtime_error naming the file on failure.
void write_png(const std::string& path, const ImageView& image);

}  // namespace ccdlane::test
