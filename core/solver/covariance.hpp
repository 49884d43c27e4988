// Rank analysis and covariance of the reduced normal matrix at the optimum: which free
// parameters the data determine, and with what uncertainty (docs/solver.md "Uncertainty").
#pragma once

#include <array>

#include <Eigen/Eigenvalues>

#include "core/solver/solver_types.hpp"

namespace ccdlane::solver {

struct CovarianceWorkspace {
  ReducedMatrix S, factor, inverse;
  ReducedVector scale;
  Eigen::SelfAdjointEigenSolver<ReducedMatrix> eigen{kMaxReducedParams};
};

struct CovarianceAnalysis {
  bool rank_deficient = false;
  int rank = 0;
  std::array<bool, kMaxReducedParams> determined{};
};

// Directions of the unit-diagonal (Jacobi-scaled) normal matrix with eigenvalue at most
// this fraction of the largest are taken as undetermined. See covariance.cpp for why.
constexpr double kRankTolerance = 1e-10;
// A parameter is undetermined when its share of the undetermined directions (the squared
// norm of its row of their unit eigenvectors) exceeds this.
constexpr double kNullShareTolerance = 1e-12;

// `N`: the reduced normal matrix (x_i eliminated, no damping). Fills `covariance` with
// variance_scale * pseudo-inverse of N over the determined directions; rows and columns
// of undetermined parameters are NaN.
CovarianceAnalysis analyse_covariance(const ReducedMatrix& N, double variance_scale, CovarianceWorkspace& ws,
                                      ReducedMatrix& covariance);

}  // namespace ccdlane::solver
