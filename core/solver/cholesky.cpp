// Cholesky factorisation, solve and inverse in plain loops (see the header).
//
// The sizes the solver meets are a handful (3 angles and a y0 per line: 5 for two
// lines), so each kernel is a template over the size, instantiated for 1..kMaxFixedSize
// and dispatched at run time (fixed_size.hpp): at a compile-time size the loops unroll completely, which
// removes the loop branches (mispredicted at every size change of the triangular loops)
// from the factorisation's serial chain of square roots and divisions. Any other size
// (larger systems, and the empty one) takes the same code with the size at run time.
#include "core/solver/cholesky.hpp"

#include <array>
#include <cmath>

#include "core/solver/fixed_size.hpp"

namespace ccdlane::solver {
namespace {

constexpr int kSizeAtRunTime = 0;

// Column-major n x n storage, as ReducedMatrix holds it.
template <int N>
struct Square {
  double* a;
  int runtime_n;
  int n() const { return N != kSizeAtRunTime ? N : runtime_n; }
  double& operator()(int r, int c) const { return a[r + c * n()]; }
};

template <int N>
bool factor(Square<N> A) {
  const int n = A.n();
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

template <int N>
bool solve(Square<N> A, double* b) {
  if (!factor(A)) return false;
  const int n = A.n();
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

// L^-1 in place of the factor L, then S^-1 = L^-T L^-1 into `inverse` (both triangles).
template <int N>
void invert_factor(Square<N> L, Square<N> inverse) {
  const int n = L.n();
  // Column by column from the left, each top-down: X(r, c) needs L's own row r right of
  // column c (not yet overwritten) and X's column c above row r.
  for (int c = 0; c < n; ++c) {
    L(c, c) = 1.0 / L(c, c);
    for (int r = c + 1; r < n; ++r) {
      double v = 0.0;
      for (int k = c; k < r; ++k) v += L(r, k) * L(k, c);
      L(r, c) = -v / L(r, r);
    }
  }
  for (int c = 0; c < n; ++c)
    for (int r = c; r < n; ++r) {
      double v = 0.0;
      for (int k = r; k < n; ++k) v += L(k, r) * L(k, c);
      inverse(r, c) = inverse(c, r) = v;
    }
}

// f<N>() with N = n where n has its fixed-size kernels, else with the size at run time.
template <class F>
bool with_square_size(int n, F&& f) {
  if (!has_fixed_size(n)) return f.template operator()<kSizeAtRunTime>();
  return with_fixed_size(n, f);
}

}  // namespace

bool cholesky_factor(ReducedMatrix& A) {
  const int n = static_cast<int>(A.rows());
  return with_square_size(n, [&]<int N>() { return factor(Square<N>{A.data(), n}); });
}

bool cholesky_solve(ReducedMatrix& A, ReducedVector& b) {
  const int n = static_cast<int>(A.rows());
  return with_square_size(n, [&]<int N>() { return solve(Square<N>{A.data(), n}, b.data()); });
}

bool invert_positive_definite(const ReducedMatrix& S, ReducedMatrix& factor_out, ReducedMatrix& inverse) {
  const int n = static_cast<int>(S.rows());
  factor_out = S;
  inverse.resize(n, n);
  return with_square_size(n, [&]<int N>() {
    if (!factor(Square<N>{factor_out.data(), n})) return false;
    invert_factor(Square<N>{factor_out.data(), n}, Square<N>{inverse.data(), n});
    return true;
  });
}

}  // namespace ccdlane::solver
