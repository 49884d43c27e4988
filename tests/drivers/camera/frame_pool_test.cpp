// The fixed frame pool: layout, alignment, borrow/return rules, and concurrent use.
#include "drivers/camera/frame_pool.hpp"

#include <atomic>
#include <cstring>
#include <set>
#include <stdexcept>
#include <thread>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(FramePool, BuffersAreDistinctAlignedAndSizedAsAsked) {
  FramePool pool({.count = 3, .width = 801, .height = 7, .format = PixelFormat::mono16});
  ASSERT_EQ(pool.size(), 3);
  EXPECT_EQ(pool.layout().stride_bytes, 1664);  // 801 * 2 = 1602, rounded up to 64
  EXPECT_EQ(pool.layout().significant_bits, 16);
  for (int i = 0; i < 3; ++i) {
    const MutableImageView& v = pool.view(i);
    EXPECT_EQ(v.width, 801);
    EXPECT_EQ(v.height, 7);
    EXPECT_EQ(v.format, PixelFormat::mono16);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(v.data) % 64, 0u);
    if (i > 0) {
      EXPECT_GE(v.data - pool.view(i - 1).data, 1664 * 7);  // no overlap
    }
  }
  // Writing the whole of one buffer leaves its neighbour untouched.
  for (int y = 0; y < 7; ++y) std::memset(pool.view(1).row(y), 0xff, 1602);
  EXPECT_EQ(pool.view(0).row(6)[1601], 0);
  EXPECT_EQ(pool.view(2).row(0)[0], 0);
}

TEST(FramePool, ExplicitStrideAndBitsAreKept) {
  FramePool pool({.count = 1,
                  .width = 10,
                  .height = 2,
                  .format = PixelFormat::mono16,
                  .stride_bytes = 100,
                  .significant_bits = 12});
  EXPECT_EQ(pool.view(0).stride_bytes, 100);
  EXPECT_EQ(pool.view(0).significant_bits, 12);
}

TEST(FramePool, BadLayoutsAreRefusedNamingTheField) {
  auto message = [](FramePoolLayout l) {
    try {
      FramePool p(l);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message({.count = 0, .width = 8, .height = 8}).find("count 0"), std::string::npos);
  EXPECT_NE(message({.count = 65, .width = 8, .height = 8}).find("count 65"), std::string::npos);
  EXPECT_NE(message({.count = 2, .width = 0, .height = 8}).find("width 0"), std::string::npos);
  EXPECT_NE(message({.count = 2, .width = 8, .height = -1}).find("height -1"), std::string::npos);
  EXPECT_NE(message({.count = 2, .width = 8, .height = 8, .format = PixelFormat::mono16, .stride_bytes = 15})
                .find("stride 15"),
            std::string::npos);
  EXPECT_NE(message({.count = 2, .width = 8, .height = 8, .significant_bits = 9}).find("significant_bits 9"),
            std::string::npos);
}

TEST(FramePool, LendsEachBufferOnceUntilGivenBack) {
  FramePool pool({.count = 3, .width = 4, .height = 4});
  std::set<int> out;
  for (int k = 0; k < 3; ++k) out.insert(pool.borrow());
  EXPECT_EQ(out, (std::set<int>{0, 1, 2}));
  EXPECT_EQ(pool.available(), 0);
  EXPECT_EQ(pool.borrow(), -1);  // exhausted: the caller drops and counts
  EXPECT_TRUE(pool.give_back(1));
  EXPECT_FALSE(pool.give_back(1));  // twice: refused
  EXPECT_FALSE(pool.give_back(3));
  EXPECT_FALSE(pool.give_back(-1));
  EXPECT_EQ(pool.available(), 1);
  EXPECT_EQ(pool.borrow(), 1);
}

TEST(FramePool, MetaTravelsWithTheIndex) {
  FramePool pool({.count = 2, .width = 4, .height = 4});
  const int i = pool.borrow();
  pool.meta(i).sequence = 42;
  pool.meta(i).t_ns = 7;
  ASSERT_TRUE(pool.give_back(i));
  EXPECT_EQ(pool.meta(i).sequence, 42u);
}

// A producer and a consumer hand buffers through the pool as the daemon's threads will:
// no index is ever held twice, and what the producer wrote is what the consumer reads.
TEST(FramePool, ProducerAndConsumerThreadsNeverShareABuffer) {
  FramePool pool({.count = 4, .width = 64, .height = 4});
  constexpr int kFrames = 20000;
  std::atomic<int> handoff{-1};
  std::atomic<bool> bad{false};
  std::thread consumer([&] {
    for (int got = 0; got < kFrames;) {
      const int i = handoff.exchange(-1, std::memory_order_acquire);
      if (i < 0) {
        std::this_thread::yield();
        continue;
      }
      const auto seq = pool.meta(i).sequence;
      if (pool.view(i).row(3)[63] != static_cast<std::uint8_t>(seq)) bad = true;
      if (!pool.give_back(i)) bad = true;
      ++got;
    }
  });
  for (int n = 0; n < kFrames;) {
    const int i = pool.borrow();
    if (i < 0) {
      std::this_thread::yield();
      continue;
    }
    pool.meta(i).sequence = static_cast<std::uint64_t>(n);
    pool.view(i).row(3)[63] = static_cast<std::uint8_t>(n);
    int expected = -1;
    while (!handoff.compare_exchange_weak(expected, i, std::memory_order_release)) {
      expected = -1;
      std::this_thread::yield();
    }
    ++n;
  }
  consumer.join();
  EXPECT_FALSE(bad);
  EXPECT_EQ(pool.available(), 4);
}

}  // namespace
}  // namespace ccdlane
