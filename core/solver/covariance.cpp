// Rank decisions on the Jacobi-scaled reduced normal matrix S = D^-1/2 N D^-1/2 (unit
// diagonal, so the decision does not depend on units: mm against radians).
//
// Why kRankTolerance = 1e-10: S is formed from products of analytic Jacobians and a Schur
// elimination per pick, so each entry carries a rounding error of a few ulps relative to
// the unit diagonal; by Weyl's theorem an exactly null direction (the roll/lane-offset
// family of docs/solver.md) then shows an eigenvalue of that order: measured |lambda| <= 2e-16
// on the synthetic road scenes of the tests. Real information is far above it: the
// weakest determined direction of the problems ccdlane meets (roll held only by a 0.5-1
// degree gyro prior) measured 2e-4..2e-3, well-posed ones 2e-2. 1e-10 lies six orders of
// magnitude from either; in terms of the scaled Jacobian's singular values (square roots)
// it flags a direction known 1e5 times worse than the parameters themselves.
//
// Why kNullShareTolerance = 1e-12: the rounding error of a computed eigenvector is about
// eps / (eigenvalue gap), <= 1e-12 even for a gap of 1e-4, so a share (squared component)
// above 1e-12 is a real coupling of the parameter to the undetermined direction. Small
// real couplings count: with free yaw, pitch and roll the roll family also moves yaw in
// proportion to sin(pitch), and such a yaw is not determined either.
#include "core/solver/covariance.hpp"

#include <cmath>
#include <limits>

#include "core/solver/cholesky.hpp"

namespace ccdlane::solver {

CovarianceAnalysis analyse_covariance(const ReducedMatrix& N, double variance_scale, CovarianceWorkspace& ws,
                                      ReducedMatrix& covariance) {
  CovarianceAnalysis out;
  const int n = static_cast<int>(N.rows());
  covariance.setZero(n, n);
  if (n == 0) return out;
  ws.scale.resize(n);
  for (int k = 0; k < n; ++k) ws.scale[k] = N(k, k) > 0.0 ? 1.0 / std::sqrt(N(k, k)) : 0.0;
  ws.S.resize(n, n);
  for (int c = 0; c < n; ++c)
    for (int r = 0; r < n; ++r) ws.S(r, c) = ws.scale[r] * N(r, c) * ws.scale[c];

  // Fast path, the usual case: lambda_min(S) >= 1 / trace(S^-1) and lambda_max(S) <=
  // trace(S) <= n, so a small trace of the inverse proves full rank without the
  // eigen-decomposition.
  if (ws.scale.minCoeff() > 0.0 && invert_positive_definite(ws.S, ws.factor, ws.inverse)) {
    const double trace = ws.inverse.trace();
    if (std::isfinite(trace) && trace > 0.0 && trace * n * kRankTolerance < 1.0) {
      out.rank = n;
      for (int k = 0; k < n; ++k) out.determined[k] = true;
      for (int c = 0; c < n; ++c)
        for (int r = 0; r < n; ++r) covariance(r, c) = variance_scale * ws.scale[r] * ws.inverse(r, c) * ws.scale[c];
      return out;
    }
  }

  ws.eigen.compute(ws.S);
  if (ws.eigen.info() != Eigen::Success) {
    out.rank_deficient = true;
    covariance.setConstant(n, n, std::numeric_limits<double>::quiet_NaN());
    return out;
  }
  const auto& values = ws.eigen.eigenvalues();  // ascending
  const auto& vectors = ws.eigen.eigenvectors();
  const double threshold = kRankTolerance * values[n - 1];

  int null_count = 0;
  while (null_count < n && !(values[null_count] > threshold)) ++null_count;
  out.rank = n - null_count;
  out.rank_deficient = null_count > 0;
  for (int k = 0; k < n; ++k) {
    // A parameter with no information at all (zero diagonal) is undetermined outright.
    const double share = vectors.row(k).head(null_count).squaredNorm();
    out.determined[k] = ws.scale[k] > 0.0 && !(share > kNullShareTolerance);
  }
  // Pseudo-inverse over the determined directions: for a parameter that the null
  // directions do not touch it is the parameter's true variance (an estimable function).
  for (int e = null_count; e < n; ++e) {
    const auto v = vectors.col(e);
    covariance.noalias() += (v / values[e]) * v.transpose();
  }
  covariance = variance_scale * (ws.scale.asDiagonal() * covariance * ws.scale.asDiagonal());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < n; ++k)
    if (!out.determined[k]) {
      covariance.row(k).setConstant(nan);
      covariance.col(k).setConstant(nan);
    }
  return out;
}

}  // namespace ccdlane::solver
