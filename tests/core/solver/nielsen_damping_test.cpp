// Nielsen's damping update: a perfect prediction divides lambda by three, a poor one
// keeps it, refusals grow it geometrically and an accepted step resets that growth.
#include "core/solver/nielsen_damping.hpp"

#include <gtest/gtest.h>

namespace ccdlane::solver {
namespace {

TEST(NielsenDamping, AGoodStepDampsLessAndAPoorOneAsBefore) {
  NielsenDamping d{1.0};
  d.accept(1.0);  // the model predicted the decrease exactly
  EXPECT_DOUBLE_EQ(d.lambda, 1.0 / 3.0);
  d.accept(0.5);  // half of it: 1 - (2 * 0.5 - 1)^3 = 1
  EXPECT_DOUBLE_EQ(d.lambda, 1.0 / 3.0);
}

TEST(NielsenDamping, RefusalsGrowFasterAndAnAcceptedStepResetsTheGrowth) {
  NielsenDamping d{1.0};
  d.reject();
  d.reject();
  EXPECT_DOUBLE_EQ(d.lambda, 8.0);  // x2 then x4
  EXPECT_DOUBLE_EQ(d.nu, 8.0);
  d.accept(0.5);
  EXPECT_DOUBLE_EQ(d.nu, 2.0);
  d.reject();
  EXPECT_DOUBLE_EQ(d.lambda, 16.0);
}

}  // namespace
}  // namespace ccdlane::solver
