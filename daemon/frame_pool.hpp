// The fixed pool of frame buffers: allocated and touched once, before the daemon is
// ready; frames are then passed between threads by index, never copied.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include "core/image/image_view.hpp"

namespace ccdlane {

class FramePool {
 public:
  // Allocates `count` frames of width x height pixels of `format` (rows tightly packed,
  // each frame starting on a cache line) and writes every page, so that none is first
  // touched on the real-time path.
  FramePool(int count, int width, int height, PixelFormat format, int significant_bits);

  int size() const { return count_; }
  std::size_t frame_bytes() const { return frame_bytes_; }
  MutableImageView view(int index) const;

 private:
  struct FreeAligned {
    void operator()(std::uint8_t* p) const;
  };
  int count_, width_, height_;
  PixelFormat format_;
  int significant_bits_;
  std::size_t stride_, frame_bytes_, frame_spacing_;
  std::unique_ptr<std::uint8_t[], FreeAligned> storage_;
};

}  // namespace ccdlane
