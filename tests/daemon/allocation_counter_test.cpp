// The counting operator new sees every form of new once armed, and nothing before.
#include "daemon/allocation_counter.hpp"

#include <memory>
#include <new>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

// Where allocations escape to, so that the compiler cannot elide an unused new/delete pair.
void* volatile g_escape = nullptr;

struct alignas(128) OverAligned {
  char bytes[128];
};

TEST(AllocationCounter, CountsEveryFormOfNewOnlyWhileArmed) {
  auto before = std::make_unique<int>(1);  // not armed: not counted
  allocation_counter::start_counting();
  EXPECT_EQ(allocation_counter::count(), 0u);

  auto one = std::make_unique<int>(2);
  g_escape = one.get();
  EXPECT_EQ(allocation_counter::count(), 1u);
  auto many = std::make_unique<int[]>(100);
  g_escape = many.get();
  EXPECT_EQ(allocation_counter::count(), 2u);
  auto aligned = std::make_unique<OverAligned>();
  EXPECT_EQ(allocation_counter::count(), 3u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned.get()) % 128, 0u);
  int* quiet = new (std::nothrow) int(3);
  g_escape = quiet;
  EXPECT_EQ(allocation_counter::count(), 4u);
  delete quiet;
  std::vector<double> v;
  v.push_back(1.0);  // the standard library allocates through operator new too
  EXPECT_EQ(allocation_counter::count(), 5u);
  std::string longer(100, 'x');
  EXPECT_EQ(allocation_counter::count(), 6u);

  allocation_counter::stop_counting();
  auto after = std::make_unique<int>(4);
  g_escape = after.get();
  EXPECT_EQ(allocation_counter::count(), 6u);
}

TEST(AllocationCounter, StartingAgainResetsTheCount) {
  allocation_counter::start_counting();
  auto p = std::make_unique<int>(1);
  g_escape = p.get();
  EXPECT_EQ(allocation_counter::count(), 1u);
  allocation_counter::start_counting();
  EXPECT_EQ(allocation_counter::count(), 0u);
  allocation_counter::stop_counting();
}

TEST(AllocationCounter, CountsPerThreadAlwaysAndOnlyThatThreadsAllocations) {
  const std::uint64_t before = allocation_counter::in_this_thread();
  auto mine = std::make_unique<int>(1);
  g_escape = mine.get();
  EXPECT_EQ(allocation_counter::in_this_thread(), before + 1);
  std::uint64_t other_thread_saw = 0;
  std::thread other([&] {
    const std::uint64_t start = allocation_counter::in_this_thread();
    auto theirs = std::make_unique<double[]>(10);
    g_escape = theirs.get();
    other_thread_saw = allocation_counter::in_this_thread() - start;
  });
  other.join();  // std::thread itself allocates in this thread, so compare what "other" saw
  EXPECT_EQ(other_thread_saw, 1u);
}

}  // namespace
}  // namespace ccdlane
