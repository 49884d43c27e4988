// An owned, packed mono image: what the tools render or decode whole frames into (the
// daemon uses the camera drivers' frame pool instead).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/image_view.hpp"

namespace ccdlane {

class ImageBuffer {
 public:
  ImageBuffer(int width, int height, PixelFormat format, int significant_bits)
      : pixels_(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                static_cast<std::size_t>(bytes_per_pixel(format))),
        view_{pixels_.data(), width,           height, static_cast<std::ptrdiff_t>(width) * bytes_per_pixel(format),
              format,         significant_bits} {}
  ImageBuffer(const ImageBuffer&) = delete;
  ImageBuffer& operator=(const ImageBuffer&) = delete;

  const MutableImageView& view() const { return view_; }

 private:
  std::vector<std::uint8_t> pixels_;
  MutableImageView view_;
};

}  // namespace ccdlane
