// The SPSC ring: order, capacity, drop-oldest, and two threads passing buffer ownership
// through it (run under ThreadSanitizer in CI: a broken hand-over is a reported race on
// the plain, non-atomic buffer contents).
#include "base/spsc_ring.hpp"

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

TEST(SpscRing, KeepsFifoOrderAndRefusesWhenFull) {
  SpscRing<std::uint32_t> ring(3);
  EXPECT_EQ(ring.capacity(), 3u);
  std::uint32_t v = 0;
  EXPECT_FALSE(ring.try_pop(v));
  EXPECT_TRUE(ring.try_push(1));
  EXPECT_TRUE(ring.try_push(2));
  EXPECT_TRUE(ring.try_push(3));
  EXPECT_FALSE(ring.try_push(4));
  EXPECT_EQ(ring.size_approx(), 3u);
  ASSERT_TRUE(ring.try_pop(v));
  EXPECT_EQ(v, 1u);
  EXPECT_TRUE(ring.try_push(4));
  for (std::uint32_t expected : {2u, 3u, 4u}) {
    ASSERT_TRUE(ring.try_pop(v));
    EXPECT_EQ(v, expected);
  }
  EXPECT_FALSE(ring.try_pop(v));
  EXPECT_EQ(ring.size_approx(), 0u);
}

TEST(SpscRing, WrapsRoundManyTimesWithACapacityThatIsNotAPowerOfTwo) {
  SpscRing<std::uint32_t> ring(5);
  std::uint32_t next_in = 0, next_out = 0, v = 0;
  for (int round = 0; round < 1000; ++round) {
    const int pushes = round % 6;  // 0..5: sometimes fills the ring exactly
    for (int i = 0; i < pushes; ++i) {
      if (ring.try_push(next_in)) ++next_in;
    }
    while (ring.try_pop(v)) EXPECT_EQ(v, next_out++);
  }
  EXPECT_EQ(next_in, next_out);
  EXPECT_GT(next_in, 2000u);
}

TEST(SpscRing, PushDroppingOldestReturnsTheOldestEntry) {
  SpscRing<std::uint32_t> ring(2);
  EXPECT_EQ(ring.push_dropping_oldest(10), std::nullopt);
  EXPECT_EQ(ring.push_dropping_oldest(11), std::nullopt);
  EXPECT_EQ(ring.push_dropping_oldest(12), std::optional<std::uint32_t>(10));
  EXPECT_EQ(ring.push_dropping_oldest(13), std::optional<std::uint32_t>(11));
  std::uint32_t v = 0;
  ASSERT_TRUE(ring.try_pop(v));
  EXPECT_EQ(v, 12u);
  EXPECT_EQ(ring.push_dropping_oldest(14), std::nullopt);
  ASSERT_TRUE(ring.try_pop(v));
  EXPECT_EQ(v, 13u);
  ASSERT_TRUE(ring.try_pop(v));
  EXPECT_EQ(v, 14u);
  EXPECT_FALSE(ring.try_pop(v));
}

TEST(SpscRing, CapacityOneStillWorks) {
  SpscRing<std::uint32_t> ring(1);
  EXPECT_TRUE(ring.try_push(1));
  EXPECT_FALSE(ring.try_push(2));
  EXPECT_EQ(ring.push_dropping_oldest(3), std::optional<std::uint32_t>(1));
  std::uint32_t v = 0;
  ASSERT_TRUE(ring.try_pop(v));
  EXPECT_EQ(v, 3u);
}

TEST(SpscRing, IndicesSitOnTheirOwnCacheLines) {
  EXPECT_GE(alignof(SpscRing<std::uint32_t>), 64u);
  EXPECT_GE(sizeof(SpscRing<std::uint32_t>), 4 * 64u);
}

// Two threads, every value once, in order, through a small ring that is often full.
TEST(SpscRingStress, TwoThreadsPassEveryValueInOrder) {
  constexpr std::uint64_t kCount = 300'000;
  SpscRing<std::uint64_t> ring(7);
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kCount; ++i) {
      while (!ring.try_push(i)) std::this_thread::yield();
    }
  });
  std::uint64_t expected = 0, v = 0;
  while (expected < kCount) {
    if (ring.try_pop(v)) {
      ASSERT_EQ(v, expected);
      ++expected;
    } else {
      std::this_thread::yield();  // on 2 cores shared with other tests, spinning starves the producer
    }
  }
  producer.join();
  EXPECT_FALSE(ring.try_pop(v));
}

// The daemon's use: a pool of plain buffers, a ring of indices to the consumer (the
// producer drops the oldest when it is full) and a ring back. Buffer contents are plain
// memory: only the rings' ordering makes the hand-over safe, which TSan checks.
TEST(SpscRingStress, DropOldestHandsBuffersOverWithoutTearingOrLosingAny) {
  constexpr int kQueue = 3;
  constexpr int kPool = kQueue + 2;  // one being filled, one being read, kQueue waiting
  constexpr std::uint64_t kFrames = 100'000;
  struct Buffer {
    std::uint64_t sequence = 0;
    std::array<std::uint64_t, 16> payload{};  // every word = sequence
  };
  std::vector<Buffer> pool(kPool);
  SpscRing<std::uint32_t> ready(kQueue);
  SpscRing<std::uint32_t> free_ring(kPool);
  for (std::uint32_t i = 0; i < kPool; ++i) ASSERT_TRUE(free_ring.try_push(i));

  std::vector<std::uint64_t> dropped;  // producer's
  dropped.reserve(kFrames);
  std::vector<std::uint64_t> consumed;  // consumer's
  consumed.reserve(kFrames);
  std::atomic<bool> done{false};

  std::thread producer([&] {
    std::uint32_t cur = 0;
    while (!free_ring.try_pop(cur)) {
    }
    for (std::uint64_t s = 0; s < kFrames; ++s) {
      pool[cur].sequence = s;
      pool[cur].payload.fill(s);
      if (auto oldest = ready.push_dropping_oldest(cur)) {
        dropped.push_back(pool[*oldest].sequence);
        cur = *oldest;
      } else {
        // Never empty here: kQueue waiting + one being read leaves one free.
        while (!free_ring.try_pop(cur)) {
        }
      }
      if (s % 4 == 0) std::this_thread::yield();  // a camera has a frame rate
    }
    done.store(true, std::memory_order_release);
  });

  auto take = [&](std::uint32_t idx) {
    const Buffer& b = pool[idx];
    for (std::uint64_t word : b.payload) ASSERT_EQ(word, b.sequence) << "torn buffer";
    consumed.push_back(b.sequence);
    // Fall behind now and then, so that the producer has to drop.
    if (consumed.size() % 64 == 0) std::this_thread::sleep_for(std::chrono::microseconds(20));
    ASSERT_TRUE(free_ring.try_push(idx));
  };
  std::uint32_t idx = 0;
  for (;;) {
    if (ready.try_pop(idx)) {
      take(idx);
    } else if (done.load(std::memory_order_acquire)) {
      if (!ready.try_pop(idx)) break;  // drained
      take(idx);
    } else {
      std::this_thread::yield();
    }
  }
  producer.join();

  // Every frame exactly once: consumed (in order) or dropped (oldest first).
  for (std::size_t i = 1; i < consumed.size(); ++i) ASSERT_LT(consumed[i - 1], consumed[i]);
  for (std::size_t i = 1; i < dropped.size(); ++i) ASSERT_LT(dropped[i - 1], dropped[i]);
  std::vector<char> seen(kFrames, 0);
  for (auto s : consumed) seen[s]++;
  for (auto s : dropped) seen[s]++;
  for (std::uint64_t s = 0; s < kFrames; ++s) ASSERT_EQ(seen[s], 1) << "frame " << s;
  EXPECT_EQ(consumed.back(), kFrames - 1) << "the newest frame is never the one dropped";
  EXPECT_GT(dropped.size(), 0u) << "the consumer's pauses should have made the producer drop";
  std::printf("frames %llu consumed %zu dropped %zu\n", static_cast<unsigned long long>(kFrames), consumed.size(),
              dropped.size());
}

}  // namespace
}  // namespace ccdlane
