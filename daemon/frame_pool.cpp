// One allocation for all frames: fewer page-table entries to lock, and the pool's size
// is plain to see in the start-up log.
#include "daemon/frame_pool.hpp"

#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>

namespace ccdlane {
namespace {
constexpr std::size_t kAlignment = 64;
}

void FramePool::FreeAligned::operator()(std::uint8_t* p) const { std::free(p); }

FramePool::FramePool(int count, int width, int height, PixelFormat format, int significant_bits)
    : count_(count), width_(width), height_(height), format_(format), significant_bits_(significant_bits) {
  if (count < 1 || width < 1 || height < 1) throw std::invalid_argument("frame pool: empty frames or no frames");
  stride_ = static_cast<std::size_t>(width) * static_cast<std::size_t>(bytes_per_pixel(format));
  frame_bytes_ = stride_ * static_cast<std::size_t>(height);
  frame_spacing_ = (frame_bytes_ + kAlignment - 1) / kAlignment * kAlignment;
  const std::size_t total = frame_spacing_ * static_cast<std::size_t>(count);
  auto* p = static_cast<std::uint8_t*>(std::aligned_alloc(kAlignment, total));
  if (!p) throw std::bad_alloc();
  std::memset(p, 0, total);
  storage_.reset(p);
}

MutableImageView FramePool::view(int index) const {
  MutableImageView v;
  v.data = storage_.get() + frame_spacing_ * static_cast<std::size_t>(index);
  v.width = width_;
  v.height = height_;
  v.stride_bytes = static_cast<std::ptrdiff_t>(stride_);
  v.format = format_;
  v.significant_bits = significant_bits_;
  return v;
}

}  // namespace ccdlane
