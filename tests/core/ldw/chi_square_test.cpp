// Chi-square and normal quantiles against published table values.
#include "core/ldw/chi_square.hpp"

#include <gtest/gtest.h>

namespace ccdlane::ldw {
namespace {

TEST(NormalQuantile, MatchesTheTableAndIsSymmetric) {
  EXPECT_NEAR(normal_quantile(0.5), 0.0, 1e-12);
  EXPECT_NEAR(normal_quantile(0.975), 1.959963985, 1e-8);
  EXPECT_NEAR(normal_quantile(0.999), 3.090232306, 1e-8);
  EXPECT_NEAR(normal_quantile(0.005), -2.575829304, 1e-8);
  EXPECT_NEAR(normal_quantile(0.2) + normal_quantile(0.8), 0.0, 1e-12);
}

// Values from the chi-square table (NIST/SEMATECH e-Handbook 1.3.6.7.4).
TEST(ChiSquareQuantile, ExactForOneAndTwoDegreesCloseBeyond) {
  EXPECT_NEAR(chi_square_quantile(1, 0.999), 10.828, 1e-3);
  EXPECT_NEAR(chi_square_quantile(1, 0.95), 3.841, 1e-3);
  EXPECT_NEAR(chi_square_quantile(2, 0.999), 13.816, 1e-3);
  EXPECT_NEAR(chi_square_quantile(3, 0.999), 16.266, 0.02 * 16.266);
  EXPECT_NEAR(chi_square_quantile(4, 0.999), 18.467, 0.015 * 18.467);
  EXPECT_NEAR(chi_square_quantile(5, 0.99), 15.086, 0.005 * 15.086);
  EXPECT_NEAR(chi_square_quantile(6, 0.999), 22.458, 0.01 * 22.458);
  EXPECT_NEAR(chi_square_quantile(100, 0.995), 140.169, 0.002 * 140.169);
  EXPECT_NEAR(chi_square_quantile(100, 0.005), 67.328, 0.002 * 67.328);
}

}  // namespace
}  // namespace ccdlane::ldw
