// The fixed frame pool: one aligned block of pixels, carved into equal buffers.
#include "drivers/camera/frame_pool.hpp"

#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

namespace ccdlane {
namespace {

constexpr std::align_val_t kAlignment{static_cast<std::size_t>(FramePool::kRowAlignment)};

std::ptrdiff_t round_up(std::ptrdiff_t v, std::ptrdiff_t to) { return (v + to - 1) / to * to; }

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("frame pool: " + what);
}

}  // namespace

void FramePool::AlignedDelete::operator()(std::uint8_t* p) const { ::operator delete[](p, kAlignment); }

FramePool::FramePool(const FramePoolLayout& layout) : layout_(layout) {
  check(layout.count >= 1 && layout.count <= kMaxFrames,
        "count " + std::to_string(layout.count) + " is not in 1.." + std::to_string(kMaxFrames));
  check(layout.width > 0 && layout.width <= 16384, "width " + std::to_string(layout.width) + " is not in 1..16384");
  check(layout.height > 0 && layout.height <= 16384, "height " + std::to_string(layout.height) + " is not in 1..16384");
  const std::ptrdiff_t min_stride = std::ptrdiff_t{layout.width} * bytes_per_pixel(layout.format);
  if (layout_.stride_bytes == 0) layout_.stride_bytes = round_up(min_stride, kRowAlignment);
  check(layout_.stride_bytes >= min_stride, "stride " + std::to_string(layout.stride_bytes) +
                                                " bytes is shorter than a row (" + std::to_string(min_stride) + ")");
  const int max_bits = layout.format == PixelFormat::mono16 ? 16 : 8;
  if (layout_.significant_bits == 0) layout_.significant_bits = max_bits;
  check(layout_.significant_bits >= 1 && layout_.significant_bits <= max_bits,
        "significant_bits " + std::to_string(layout.significant_bits) + " is not in 1.." + std::to_string(max_bits));

  // Each buffer starts on an aligned boundary too, whatever the stride.
  const std::ptrdiff_t buffer_bytes = round_up(layout_.stride_bytes * layout.height, kRowAlignment);
  const auto total = static_cast<std::size_t>(buffer_bytes * layout.count);
  pixels_.reset(static_cast<std::uint8_t*>(::operator new[](total, kAlignment)));
  std::memset(pixels_.get(), 0, total);  // touch every page now, not on the first frame

  views_.resize(static_cast<std::size_t>(layout.count));
  metas_.resize(static_cast<std::size_t>(layout.count));
  borrowed_ = std::make_unique<std::atomic<bool>[]>(static_cast<std::size_t>(layout.count));
  for (int i = 0; i < layout.count; ++i) {
    views_[static_cast<std::size_t>(i)] = MutableImageView{
        pixels_.get() + buffer_bytes * i, layout.width, layout.height, layout_.stride_bytes, layout.format,
        layout_.significant_bits};
    borrowed_[static_cast<std::size_t>(i)].store(false, std::memory_order_relaxed);
  }
}

int FramePool::borrow() {
  const int n = size();
  const unsigned start = next_hint_.fetch_add(1, std::memory_order_relaxed);
  for (int k = 0; k < n; ++k) {
    const int i = static_cast<int>((start + static_cast<unsigned>(k)) % static_cast<unsigned>(n));
    bool expected = false;
    // acquire: the previous holder's writes to pixels and meta happen before ours.
    if (borrowed_[static_cast<std::size_t>(i)].compare_exchange_strong(expected, true, std::memory_order_acquire,
                                                                       std::memory_order_relaxed))
      return i;
  }
  return -1;
}

bool FramePool::give_back(int index) {
  if (index < 0 || index >= size()) return false;
  bool expected = true;
  // release: our writes (or reads) of the buffer are done before the next borrower's.
  return borrowed_[static_cast<std::size_t>(index)].compare_exchange_strong(expected, false, std::memory_order_release,
                                                                            std::memory_order_relaxed);
}

int FramePool::available() const {
  int n = 0;
  for (int i = 0; i < size(); ++i) n += borrowed_[static_cast<std::size_t>(i)].load(std::memory_order_relaxed) ? 0 : 1;
  return n;
}

}  // namespace ccdlane
