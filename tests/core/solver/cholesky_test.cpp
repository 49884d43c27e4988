// The small Cholesky solve and inverse against Eigen's, and their refusal of matrices
// that are not positive definite.
#include "core/solver/cholesky.hpp"

#include <limits>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "tests/core/solver/random_matrix.hpp"

namespace ccdlane::solver {
namespace {

TEST(CholeskySolve, MatchesEigenOnRandomPositiveDefiniteSystems) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int n = 1; n <= kMaxReducedParams; ++n) {
    const Eigen::MatrixXd B = test::gaussian_matrix(rng, n + 3, n);
    const Eigen::MatrixXd spd = B.transpose() * B + 1e-3 * Eigen::MatrixXd::Identity(n, n);
    Eigen::VectorXd b(n);
    for (int k = 0; k < n; ++k) b[k] = g(rng);
    const Eigen::VectorXd expected = spd.llt().solve(b);
    ReducedMatrix A = spd;
    A.triangularView<Eigen::StrictlyUpper>().setConstant(1e300);  // only the lower triangle is read
    ReducedVector x = b;
    ASSERT_TRUE(cholesky_solve(A, x)) << n;
    const double cond = spd.norm() * spd.inverse().norm();
    EXPECT_LE((x - expected).norm(), 1e-13 * cond * expected.norm()) << n;
  }
}

TEST(CholeskySolve, RefusesMatricesThatAreNotPositiveDefinite) {
  ReducedMatrix semi(2, 2);
  semi << 1.0, 1.0, 1.0, 1.0;  // singular
  ReducedVector b(2);
  b << 1.0, 2.0;
  EXPECT_FALSE(cholesky_solve(semi, b));
  ReducedMatrix indefinite(2, 2);
  indefinite << 1.0, 2.0, 2.0, 1.0;
  EXPECT_FALSE(cholesky_solve(indefinite, b));
  ReducedMatrix nan(1, 1);
  nan << std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(cholesky_solve(nan, b));
}

TEST(CholeskySolve, EmptySystemHasTheEmptySolution) {
  ReducedMatrix A(0, 0);
  ReducedVector b(0);
  EXPECT_TRUE(cholesky_solve(A, b));
  ReducedMatrix factor, inverse;
  EXPECT_TRUE(invert_positive_definite(A, factor, inverse));
  EXPECT_EQ(inverse.rows(), 0);
}

TEST(CholeskyInverse, MatchesEigenOnPositiveDefiniteMatricesOfEverySize) {
  std::mt19937_64 rng(7);
  for (int n = 1; n <= kMaxReducedParams; ++n) {
    const Eigen::MatrixXd J = test::gaussian_matrix(rng, n + 4, n);
    const ReducedMatrix S = J.transpose() * J;
    ReducedMatrix factor, inverse;
    ASSERT_TRUE(invert_positive_definite(S, factor, inverse)) << n;
    const Eigen::MatrixXd expected = Eigen::MatrixXd(S).inverse();
    const double cond = S.norm() * expected.norm();
    EXPECT_LE((Eigen::MatrixXd(inverse) - expected).norm(), 1e-14 * cond * expected.norm()) << n;
  }
  ReducedMatrix singular(2, 2), factor, inverse;
  singular << 1.0, 1.0, 1.0, 1.0;
  EXPECT_FALSE(invert_positive_definite(singular, factor, inverse));
}

}  // namespace
}  // namespace ccdlane::solver
