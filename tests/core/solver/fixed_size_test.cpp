// The size dispatch of the solver's fixed-size kernels: every size of its range reaches
// its own instantiation, and any other size is a caller's bug that stops the program
// (before the fix it ran the kernel of the largest size on storage sized for another).
#include "core/solver/fixed_size.hpp"

#include <gtest/gtest.h>

#include "core/solver/lane_solver.hpp"

namespace ccdlane::solver {
namespace {

constexpr auto kInstantiatedSize = []<int N>() { return N; };

TEST(WithFixedSize, EachSizeOfTheRangeReachesItsOwnInstantiation) {
  for (int n = 1; n <= kMaxFixedSize; ++n) {
    EXPECT_TRUE(has_fixed_size(n)) << n;
    EXPECT_EQ(with_fixed_size(n, kInstantiatedSize), n);
  }
}

TEST(WithFixedSizeDeathTest, SizeOutsideTheRangeStopsTheProgram) {
  // 0: a layout with nothing free; above: a reduced system too large for the kernels.
  for (const int n : {0, -1, kMaxFixedSize + 1, kMaxReducedParams}) {
    EXPECT_FALSE(has_fixed_size(n)) << n;
    EXPECT_DEATH(with_fixed_size(n, kInstantiatedSize), "") << "size " << n;
  }
}

}  // namespace
}  // namespace ccdlane::solver
