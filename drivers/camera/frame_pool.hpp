// The fixed pool of frame buffers a capture thread fills and the processing thread reads:
// allocated once at start, lent out by index (the daemon's ring carries indices, not pixels).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "base/image_view.hpp"
#include "drivers/frame_source.hpp"

namespace ccdlane {

struct FramePoolLayout {
  int count = 4;
  int width = 0;
  int height = 0;
  PixelFormat format = PixelFormat::mono8;
  std::ptrdiff_t stride_bytes = 0;  // 0: width * bytes per pixel, rounded up to kRowAlignment
  int significant_bits = 0;         // 0: 8 for mono8, 16 for mono16
};

class FramePool {
 public:
  static constexpr int kMaxFrames = 64;
  static constexpr std::ptrdiff_t kRowAlignment = 64;  // rows start on a cache line (SIMD loads)

  // Allocates and touches every buffer now, so no page is faulted in on the real-time
  // path. Throws std::invalid_argument naming the bad field of `layout`.
  explicit FramePool(const FramePoolLayout& layout);
  FramePool(const FramePool&) = delete;
  FramePool& operator=(const FramePool&) = delete;

  int size() const { return static_cast<int>(views_.size()); }
  const FramePoolLayout& layout() const { return layout_; }

  // Lends a free buffer: its index, or -1 when all are out (the caller drops and counts).
  // Lock-free and allocation-free; any thread may borrow or give back.
  int borrow();
  // Returns a borrowed buffer. False (and nothing changes) for an index that is out of
  // range or not currently borrowed: a programmer error the caller should count/log.
  [[nodiscard]] bool give_back(int index);
  int available() const;

  // The buffer's pixels and its metadata; valid while the caller holds the index.
  const MutableImageView& view(int index) const { return views_[static_cast<std::size_t>(index)]; }
  FrameMeta& meta(int index) { return metas_[static_cast<std::size_t>(index)]; }
  const FrameMeta& meta(int index) const { return metas_[static_cast<std::size_t>(index)]; }

 private:
  struct AlignedDelete {
    void operator()(std::uint8_t* p) const;
  };

  FramePoolLayout layout_;
  std::unique_ptr<std::uint8_t, AlignedDelete> pixels_;
  std::vector<MutableImageView> views_;
  std::vector<FrameMeta> metas_;
  std::unique_ptr<std::atomic<bool>[]> borrowed_;
  std::atomic<unsigned> next_hint_{0};  // round-robin start, so buffers are used evenly
};

}  // namespace ccdlane
