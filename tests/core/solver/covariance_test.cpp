// Rank analysis on normal matrices with known null spaces, and the covariance of what is
// determined.
#include "core/solver/covariance.hpp"

#include <cmath>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "tests/core/solver/random_matrix.hpp"

namespace ccdlane::solver {
namespace {

TEST(Covariance, FullRankGivesTheScaledInverse) {
  std::mt19937_64 rng(1);
  Eigen::MatrixXd J = test::gaussian_matrix(rng, 40, 6);
  J.col(2) *= 1e4;  // mm against radians: units must not matter
  J.col(4) *= 1e-3;
  const ReducedMatrix N = J.transpose() * J;
  CovarianceWorkspace ws;
  ReducedMatrix cov;
  const CovarianceAnalysis a = analyse_covariance(N, 2.5, ws, cov);
  EXPECT_FALSE(a.rank_deficient);
  EXPECT_EQ(a.rank, 6);
  const Eigen::MatrixXd expected = 2.5 * Eigen::MatrixXd(N).inverse();
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c)
      EXPECT_NEAR(cov(r, c), expected(r, c), 1e-9 * std::sqrt(expected(r, r) * expected(c, c)));
}

TEST(Covariance, ExactNullDirectionMarksOnlyItsParametersUndetermined) {
  std::mt19937_64 rng(2);
  // Parameters 1 and 3 move together without changing anything (like roll and a line's
  // offset); 0, 2 and 4 are determined.
  Eigen::MatrixXd J = test::gaussian_matrix(rng, 30, 5);
  J.col(3) = -2.0e3 * J.col(1);
  const ReducedMatrix N = J.transpose() * J;
  CovarianceWorkspace ws;
  ReducedMatrix cov;
  const CovarianceAnalysis a = analyse_covariance(N, 1.0, ws, cov);
  EXPECT_TRUE(a.rank_deficient);
  EXPECT_EQ(a.rank, 4);
  EXPECT_FALSE(a.determined[1]);
  EXPECT_FALSE(a.determined[3]);
  EXPECT_TRUE(std::isnan(cov(1, 1)) && std::isnan(cov(3, 3)) && std::isnan(cov(0, 1)));
  // The others keep their true variance: that of the problem with the pair merged.
  Eigen::MatrixXd merged(30, 4);
  merged << J.col(0), J.col(1), J.col(2), J.col(4);
  const Eigen::MatrixXd expected = (merged.transpose() * merged).inverse();
  const int kept[3] = {0, 2, 4}, in_merged[3] = {0, 2, 3};
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(a.determined[kept[i]]);
    EXPECT_NEAR(cov(kept[i], kept[i]), expected(in_merged[i], in_merged[i]),
                1e-9 * expected(in_merged[i], in_merged[i]));
  }
}

TEST(Covariance, ParameterWithoutInformationIsUndetermined) {
  std::mt19937_64 rng(3);
  Eigen::MatrixXd J = test::gaussian_matrix(rng, 20, 4);
  J.col(2).setZero();  // e.g. a line without picks
  CovarianceWorkspace ws;
  ReducedMatrix cov;
  const CovarianceAnalysis a = analyse_covariance(J.transpose() * J, 1.0, ws, cov);
  EXPECT_TRUE(a.rank_deficient);
  EXPECT_FALSE(a.determined[2]);
  EXPECT_TRUE(a.determined[0] && a.determined[1] && a.determined[3]);
  EXPECT_TRUE(std::isfinite(cov(0, 0)));
}

TEST(Covariance, WeakButRealInformationIsNotRankDeficiency) {
  // A direction 1e4 times less well known than the parameters (information ratio 1e-8)
  // is still determined, with a correspondingly large sigma.
  std::mt19937_64 rng(4);
  Eigen::MatrixXd J = test::gaussian_matrix(rng, 30, 3);
  const Eigen::VectorXd other = test::gaussian_matrix(rng, 30, 1).col(0).normalized();
  J.col(2) = J.col(1) + 1e-4 * other * J.col(1).norm();
  const ReducedMatrix N = J.transpose() * J;
  CovarianceWorkspace ws;
  ReducedMatrix cov;
  const CovarianceAnalysis a = analyse_covariance(N, 1.0, ws, cov);
  EXPECT_FALSE(a.rank_deficient);
  const Eigen::MatrixXd expected = Eigen::MatrixXd(N).inverse();
  EXPECT_NEAR(cov(2, 2), expected(2, 2), 1e-4 * expected(2, 2));
}

}  // namespace
}  // namespace ccdlane::solver
