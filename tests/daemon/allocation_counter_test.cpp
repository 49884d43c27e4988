// The counting operator new sees every form of new once armed, and nothing before.
#include "daemon/allocation_counter.hpp"

#include <memory>
#include <new>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ccdlane {
namespace {

struct alignas(128) OverAligned {
  char bytes[128];
};

TEST(AllocationCounter, CountsEveryFormOfNewOnlyWhileArmed) {
  auto before = std::make_unique<int>(1);  // not armed: not counted
  allocation_counter::start_counting();
  EXPECT_EQ(allocation_counter::count(), 0u);

  auto one = std::make_unique<int>(2);
  EXPECT_EQ(allocation_counter::count(), 1u);
  auto many = std::make_unique<int[]>(100);
  EXPECT_EQ(allocation_counter::count(), 2u);
  auto aligned = std::make_unique<OverAligned>();
  EXPECT_EQ(allocation_counter::count(), 3u);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(aligned.get()) % 128, 0u);
  int* quiet = new (std::nothrow) int(3);
  EXPECT_EQ(allocation_counter::count(), 4u);
  delete quiet;
  std::vector<double> v;
  v.push_back(1.0);  // the standard library allocates through operator new too
  EXPECT_EQ(allocation_counter::count(), 5u);
  std::string longer(100, 'x');
  EXPECT_EQ(allocation_counter::count(), 6u);

  allocation_counter::stop_counting();
  auto after = std::make_unique<int>(4);
  EXPECT_EQ(allocation_counter::count(), 6u);
}

TEST(AllocationCounter, StartingAgainResetsTheCount) {
  allocation_counter::start_counting();
  auto p = std::make_unique<int>(1);
  EXPECT_EQ(allocation_counter::count(), 1u);
  allocation_counter::start_counting();
  EXPECT_EQ(allocation_counter::count(), 0u);
  allocation_counter::stop_counting();
}

}  // namespace
}  // namespace ccdlane
