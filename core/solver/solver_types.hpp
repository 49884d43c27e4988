// Fixed-capacity Eigen types and per-pick blocks shared by the pieces of the lane solver.
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

// One pick's linearisation: residuals r (2), d r / d(local parameters), d r / d x_i.
struct PickBlock {
  Vec2 r = Vec2::Zero();
  PickJacobian J = PickJacobian::Zero();
  Vec2 Jx = Vec2::Zero();
};

// One prior's whitened residual and its (dense) row over the reduced parameters.
struct PriorRow {
  double r = 0.0;
  ReducedVector a;
};

struct PriorRows {
  int count = 0;
  std::array<PriorRow, kMaxPriors> rows;
};

}  // namespace ccdlane::solver
