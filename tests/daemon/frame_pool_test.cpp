// The pool: distinct, aligned, zeroed frames of the asked size.
#include "daemon/frame_pool.hpp"

#include <cstdint>
#include <stdexcept>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(FramePool, FramesAreDistinctAlignedAndOfTheAskedSize) {
  FramePool pool(6, 801, 3, PixelFormat::mono16, 12);
  EXPECT_EQ(pool.size(), 6);
  EXPECT_EQ(pool.frame_bytes(), 801u * 2 * 3);
  for (int i = 0; i < pool.size(); ++i) {
    const MutableImageView v = pool.view(i);
    EXPECT_EQ(v.width, 801);
    EXPECT_EQ(v.height, 3);
    EXPECT_EQ(v.stride_bytes, 1602);
    EXPECT_EQ(v.format, PixelFormat::mono16);
    EXPECT_EQ(v.significant_bits, 12);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data) % 64, 0u);
    for (std::size_t b = 0; b < pool.frame_bytes(); ++b) ASSERT_EQ(v.data[b], 0);
    if (i > 0) {
      EXPECT_GE(v.data, pool.view(i - 1).data + pool.frame_bytes()) << "frames overlap";
    }
  }
}

TEST(FramePool, WritingOneFrameLeavesTheOthersAlone) {
  FramePool pool(3, 16, 4, PixelFormat::mono8, 8);
  const MutableImageView middle = pool.view(1);
  for (int y = 0; y < middle.height; ++y)
    for (int x = 0; x < middle.width; ++x) middle.row(y)[x] = 0xff;
  for (int i : {0, 2}) {
    const MutableImageView v = pool.view(i);
    for (std::size_t b = 0; b < pool.frame_bytes(); ++b) ASSERT_EQ(v.data[b], 0) << "frame " << i;
  }
}

TEST(FramePool, RefusesAnEmptyPool) {
  EXPECT_THROW(FramePool(0, 8, 8, PixelFormat::mono8, 8), std::invalid_argument);
  EXPECT_THROW(FramePool(2, 0, 8, PixelFormat::mono8, 8), std::invalid_argument);
}

}  // namespace
}  // namespace ccdlane
