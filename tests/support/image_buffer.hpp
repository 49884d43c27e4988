// A picture a test owns: its bytes (filled with 0xEE, a value no decoder writes by
// chance) and the view over them, optionally with padding at each row's end (a stride
// wider than the pixels, as camera buffers have).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/image_view.hpp"

namespace ccdlane::test {

struct ImageBuffer {
  std::vector<std::uint8_t> bytes;
  MutableImageView view;
  ImageBuffer(int w, int h, PixelFormat f = PixelFormat::mono8, int stride_extra = 0) {
    const std::ptrdiff_t stride = w * bytes_per_pixel(f) + stride_extra;
    bytes.assign(static_cast<std::size_t>(stride * h), 0xEE);
    view = {bytes.data(), w, h, stride, f, f == PixelFormat::mono16 ? 16 : 8};
  }
};

}  // namespace ccdlane::test
