// The doorbell: a ring wakes a sleeper, a ring before the sleep is not lost, and an
// unrung wait ends at its timeout.
#include "daemon/doorbell.hpp"

#include <atomic>
#include <chrono>
#include <thread>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

using Clock = std::chrono::steady_clock;

TEST(Doorbell, ARingBetweenLookAndSleepIsNotLost) {
  Doorbell bell;
  const std::uint32_t seen = bell.value();
  bell.ring();  // before the wait: the wait must return at once
  const auto before = Clock::now();
  bell.wait(seen, 5000);
  EXPECT_LT(Clock::now() - before, std::chrono::seconds(1));
  EXPECT_NE(bell.value(), seen);
}

TEST(Doorbell, ARingWakesASleeper) {
  Doorbell bell;
  std::atomic<bool> woke{false};
  std::thread sleeper([&] {
    const std::uint32_t seen = bell.value();
    while (bell.value() == seen) bell.wait(seen, 5000);
    woke = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto before = Clock::now();
  bell.ring();
  sleeper.join();
  EXPECT_TRUE(woke);
  EXPECT_LT(Clock::now() - before, std::chrono::seconds(2)) << "woken by the ring, not by the 5 s timeout";
}

TEST(Doorbell, AnUnrungWaitEndsAtItsTimeout) {
  Doorbell bell;
  const auto before = Clock::now();
  bell.wait(bell.value(), 30);
  const auto took = Clock::now() - before;
  EXPECT_GE(took, std::chrono::milliseconds(25));
  EXPECT_LT(took, std::chrono::seconds(2));
}

}  // namespace
}  // namespace ccdlane
