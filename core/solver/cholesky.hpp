// Unpivoted Cholesky factorisation of the solver's small dense systems (at most
// kMaxReducedParams unknowns), where plain loops beat a general pivoting factorisation
// several times over: the damped LM step and the full-rank covariance.
#pragma once

#include "core/solver/solver_types.hpp"

namespace ccdlane::solver {

// A = L L^T in place: L into A's lower triangle (only the lower triangle is read). False
// when a pivot is not positive (A is not positive definite to working precision).
bool cholesky_factor(ReducedMatrix& A);

// Solves A x = b in place (x into b); A is factored in place. False as cholesky_factor.
bool cholesky_solve(ReducedMatrix& A, ReducedVector& b);

// The inverse of a symmetric positive definite S (its lower triangle is read) through its
// Cholesky factor L (into `factor`): S^-1 = L^-T L^-1. False as cholesky_factor.
bool invert_positive_definite(const ReducedMatrix& S, ReducedMatrix& factor, ReducedMatrix& inverse);

}  // namespace ccdlane::solver
