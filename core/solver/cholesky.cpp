// Cholesky factorisation, solve and inverse in plain loops (see the header).
#include "core/solver/cholesky.hpp"

#include <array>
#include <cmath>

namespace ccdlane::solver {

bool cholesky_factor(ReducedMatrix& A) {
  const int n = static_cast<int>(A.rows());
  for (int c = 0; c < n; ++c) {
    double pivot = A(c, c);
    for (int k = 0; k < c; ++k) pivot -= A(c, k) * A(c, k);
    if (!(pivot > 0.0)) return false;
    const double d = std::sqrt(pivot);
    A(c, c) = d;
    const double inv_d = 1.0 / d;
    for (int r = c + 1; r < n; ++r) {
      double v = A(r, c);
      for (int k = 0; k < c; ++k) v -= A(r, k) * A(c, k);
      A(r, c) = v * inv_d;
    }
  }
  return true;
}

bool cholesky_solve(ReducedMatrix& A, ReducedVector& b) {
  if (!cholesky_factor(A)) return false;
  const int n = static_cast<int>(A.rows());
  // The diagonal's reciprocals: the solves below are serial chains, and a multiplication
  // is a fraction of a division's latency.
  std::array<double, kMaxReducedParams> inv_diag{};
  for (int c = 0; c < n; ++c) inv_diag[c] = 1.0 / A(c, c);
  for (int r = 0; r < n; ++r) {  // L y = b
    for (int k = 0; k < r; ++k) b[r] -= A(r, k) * b[k];
    b[r] *= inv_diag[r];
  }
  for (int r = n - 1; r >= 0; --r) {  // L^T x = y
    for (int k = r + 1; k < n; ++k) b[r] -= A(k, r) * b[k];
    b[r] *= inv_diag[r];
  }
  return true;
}

bool invert_positive_definite(const ReducedMatrix& S, ReducedMatrix& factor, ReducedMatrix& inverse) {
  const int n = static_cast<int>(S.rows());
  ReducedMatrix& L = factor;
  L = S;
  if (!cholesky_factor(L)) return false;
  // L^-1 in place of L, column by column from the left, each top-down: X(r, c) needs
  // L's own row r right of column c (not yet overwritten) and X's column c above row r.
  for (int c = 0; c < n; ++c) {
    L(c, c) = 1.0 / L(c, c);
    for (int r = c + 1; r < n; ++r) {
      double v = 0.0;
      for (int k = c; k < r; ++k) v += L(r, k) * L(k, c);
      L(r, c) = -v / L(r, r);
    }
  }
  inverse.resize(n, n);
  for (int c = 0; c < n; ++c)
    for (int r = c; r < n; ++r) {
      double v = 0.0;
      for (int k = r; k < n; ++k) v += L(k, r) * L(k, c);
      inverse(r, c) = inverse(c, r) = v;
    }
  return true;
}

}  // namespace ccdlane::solver
