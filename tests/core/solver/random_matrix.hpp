// Random dense matrices for the solver's linear-algebra tests.
#pragma once

#include <random>

#include <Eigen/Core>

namespace ccdlane::test {

// A rows x cols matrix of independent standard normal entries.
inline Eigen::MatrixXd gaussian_matrix(std::mt19937_64& rng, int rows, int cols) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) m(r, c) = g(rng);
  return m;
}

}  // namespace ccdlane::test
