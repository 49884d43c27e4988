// The LM loop's small Cholesky solve against Eigen's, and its refusal of matrices that
// are not positive definite.
#include <limits>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "core/solver/levenberg_marquardt.hpp"

namespace ccdlane::solver {
namespace {

TEST(CholeskySolve, MatchesEigenOnRandomPositiveDefiniteSystems) {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int n = 1; n <= kMaxReducedParams; ++n) {
    Eigen::MatrixXd B(n + 3, n);
    for (int r = 0; r < B.rows(); ++r)
      for (int c = 0; c < n; ++c) B(r, c) = g(rng);
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

}  // namespace
}  // namespace ccdlane::solver
