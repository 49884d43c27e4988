// Fixed-capacity Eigen types and the per-pick rows shared by the pieces of the lane solver.
#pragma once

#include <array>

#include "core/geometry/types.hpp"
#include "core/solver/lane_solver.hpp"

namespace ccdlane::solver {

// A pick's residuals touch the free globals and the free kinds of its own line only:
// at most 5 + 3 local columns (zero-padded, so the per-pick algebra is fixed-size).
constexpr int kMaxLocalParams = kPoseParams + 3;
constexpr int kMaxPriors = 6;  // psi, theta, phi, H, f, lane width

using ReducedVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxReducedParams, 1>;
using LocalVector = Eigen::Matrix<double, kMaxLocalParams, 1>;
using LocalMatrix = Eigen::Matrix<double, kMaxLocalParams, kMaxLocalParams>;
using PickJacobian = Eigen::Matrix<double, 2, kMaxLocalParams>;

// The picks' linearisation, one array per quantity over the picks (structure of arrays,
// so that every pass over the picks is a vectorised array expression), in the form the
// Schur elimination of each pick's x_i needs: the residuals and their Jacobian rows seen
// along two orthogonal directions of equal length, b_x = Jx (= d r / d x_i) and b_u = Jx
// turned by 90 degrees. Along b_u nothing x_i does can help, so that row enters the
// reduced system whole; the b_x row is what x_i absorbs (all of it undamped, a share
// when damped). Unnormalised, so that no square root sits on the projection's path.
struct PickRows {
  using Array = Eigen::ArrayXd;
  explicit PickRows(int max_picks);

  Array r0, r1;                               // residuals
  Array jx0, jx1;                             // d r / d x_i
  Array ru, rx;                               // b_u.r and b_x.r
  Array w;                                    // 1 / |Jx|^2
  std::array<Array, kMaxLocalParams> au, ax;  // b_u^T and b_x^T d r / d(local parameter k)

  // Pick i from its residuals and their Jacobians over the first m local parameters (J)
  // and its x (Jx); call complete() once every pick is set.
  void set(int i, const Vec2& r, const PickJacobian& J, const Vec2& Jx, int m);
  // ru, rx and w from r and Jx, for picks i < n. False when some pick's x moves nothing
  // (Jx = 0): it cannot be eliminated. Never so for a road point in view of a camera
  // above the road (the road's directions are not rays through the lens).
  bool complete(int n);

  // Back in residual coordinates, for checks: d r_i / d(local parameter k), d r_i / d x_i.
  Vec2 residual(int i) const { return {r0[i], r1[i]}; }
  Vec2 jx(int i) const { return {jx0[i], jx1[i]}; }
  Vec2 jacobian_column(int i, int k) const {
    return (au[k][i] * Vec2(-jx1[i], jx0[i]) + ax[k][i] * jx(i)) / jx(i).squaredNorm();
  }
};

// Picks sorted by line: line j's picks are [begin[j], begin[j + 1]).
struct LineSegments {
  std::array<int, kMaxLaneLines + 1> begin{};
  int size(int line) const { return begin[line + 1] - begin[line]; }
};

// The picks' share of the reduced normal equations, per line over its local parameters:
// a part x_i cannot absorb (fixed) and the part it absorbs unless damped (damped). With
// x_i's curvature damped by (1 + lambda) the line's block is fixed + lambda / (1 + lambda)
// damped, so a rejected step (a new lambda) costs no pass over the picks, nor does the
// covariance at the optimum.
struct LineNormals {
  std::array<LocalMatrix, kMaxLaneLines> H_fixed, H_damped;
  std::array<LocalVector, kMaxLaneLines> h_fixed, h_damped;
};

// One prior's whitened residual and its row over the reduced parameters. A prior touches
// at most two of them (the lane width: two lines' y0), so the row is kept as its nonzero
// entries: the reduced system takes it in a few operations rather than a pass over n^2.
struct PriorRow {
  double r = 0.0;
  int size = 0;  // entries in use
  std::array<int, 2> index{};
  std::array<double, 2> value{};

  // Adds v at reduced index k (nothing when k < 0: a fixed parameter).
  void add(int k, double v) {
    if (k < 0) return;
    for (int e = 0; e < size; ++e)
      if (index[e] == k) {
        value[e] += v;
        return;
      }
    index[size] = k;
    value[size++] = v;
  }
  // The row's entry at reduced index k.
  double at(int k) const {
    for (int e = 0; e < size; ++e)
      if (index[e] == k) return value[e];
    return 0.0;
  }
};

struct PriorRows {
  int count = 0;
  std::array<PriorRow, kMaxPriors> rows;
};

}  // namespace ccdlane::solver
