// Schur elimination of the x_i against the full dense system: the same step, the same
// x_i steps, and the linearised cost decrease computed directly.
#include "core/solver/schur_system.hpp"

#include <array>
#include <random>
#include <vector>

#include <Eigen/Dense>
#include <gtest/gtest.h>

namespace ccdlane::solver {
namespace {

struct RandomProblem {
  ParameterLayout layout;
  std::vector<Pick> picks;  // sorted by line, as the solver keeps them
  LineSegments segments;
  std::vector<PickJacobian> J;  // each pick's Jacobian over its local parameters
  std::vector<Vec2> Jx, r;      // and over its x, and its residuals
  PickRows rows;
  std::vector<double> x;
  SolverState state;

  RandomProblem(std::uint64_t seed, FreeSet free, int num_lines, int num_picks)
      : layout(free, num_lines), rows(num_picks) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> g(0.0, 1.0);
    for (int i = 0; i < num_picks; ++i) {
      const int line = i * num_lines / num_picks;
      picks.push_back({line, 0.0, 0.0});
      segments.begin[line + 1] = i + 1;
      PickJacobian Ji = PickJacobian::Zero();
      for (int c = 0; c < layout.local_size(); ++c) Ji.col(c) = Vec2(g(rng), g(rng));
      J.push_back(Ji);
      Jx.emplace_back(g(rng), g(rng));
      r.emplace_back(g(rng), g(rng));
      rows.set(i, r.back(), J.back(), Jx.back(), layout.local_size());
    }
    EXPECT_TRUE(rows.complete(num_picks));
    x.assign(num_picks, 0.0);
    state.rows = &rows;
    state.x = x.data();
    // Two prior rows (one coupling two lines' y0, like the lane width).
    state.priors.count = 2;
    for (PriorRow& row : state.priors.rows) row.r = g(rng);
    state.priors.rows[0].add(0, 2.0);
    state.priors.rows[1].add(layout.line_index(0, kY0), 1.5);
    state.priors.rows[1].add(layout.line_index(num_lines - 1, kY0), -1.5);
    accumulate_normals(layout, segments, state);
  }

  // The whole Jacobian over (reduced parameters, x_1..x_N), rows of picks then priors.
  Eigen::MatrixXd full_jacobian() const {
    const int n = layout.size(), N = static_cast<int>(picks.size());
    Eigen::MatrixXd full = Eigen::MatrixXd::Zero(2 * N + state.priors.count, n + N);
    for (int i = 0; i < N; ++i) {
      const int line = picks[i].line;
      for (int c = 0; c < layout.num_global(); ++c) full.block<2, 1>(2 * i, c) = J[i].col(c);
      for (int c = 0; c < layout.num_line_kinds(); ++c)
        full.block<2, 1>(2 * i, layout.line_offset(line) + c) = J[i].col(layout.num_global() + c);
      full.block<2, 1>(2 * i, n + i) = Jx[i];
    }
    for (int k = 0; k < state.priors.count; ++k)
      for (int c = 0; c < n; ++c) full(2 * N + k, c) = state.priors.rows[k].at(c);
    return full;
  }
  Eigen::VectorXd full_residual() const {
    const int N = static_cast<int>(picks.size());
    Eigen::VectorXd full(2 * N + state.priors.count);
    for (int i = 0; i < N; ++i) full.segment<2>(2 * i) = r[i];
    for (int k = 0; k < state.priors.count; ++k) full[2 * N + k] = state.priors.rows[k].r;
    return full;
  }
};

TEST(SchurSystem, ReducedStepEqualsTheFullSystemsStep) {
  using enum FreeParam;
  FreeSet free;
  for (FreeParam p : {psi, theta, phi, H, y0, m, c}) free.add(p);
  for (const double lambda : {0.0, 1e-3, 0.5}) {
    RandomProblem p(11, free, 3, 12);
    const int n = p.layout.size(), N = 12;
    const Eigen::MatrixXd J = p.full_jacobian();
    const Eigen::VectorXd r = p.full_residual();
    // Full system with the x_i's curvature damped by (1 + lambda), as the solver does.
    Eigen::MatrixXd A = J.transpose() * J;
    for (int i = 0; i < N; ++i) A(n + i, n + i) *= 1.0 + lambda;
    const Eigen::VectorXd full = A.ldlt().solve(-J.transpose() * r);

    ReducedMatrix Nr;
    ReducedVector g;
    build_reduced_system(p.layout, p.state, lambda, Nr, g);
    const ReducedVector step = Nr.ldlt().solve(-g);
    for (int k = 0; k < n; ++k) EXPECT_NEAR(step[k], full[k], 1e-9 * (1 + std::abs(full[k]))) << "lambda " << lambda;
    std::vector<double> dx(N);
    const BackSubstitution bs = back_substitute(p.layout, p.segments, p.state, lambda, step, dx.data());
    double dx2 = 0.0;
    for (int i = 0; i < N; ++i) {
      EXPECT_NEAR(dx[i], full[n + i], 1e-9 * (1 + std::abs(full[n + i])));
      dx2 += dx[i] * dx[i];
    }
    EXPECT_NEAR(bs.x_step_squared_norm, dx2, 1e-12 * dx2);
    Eigen::VectorXd delta(n + N);
    delta << step, Eigen::Map<const Eigen::VectorXd>(dx.data(), N);
    const double predicted = r.squaredNorm() - (r + J * delta).squaredNorm();
    EXPECT_NEAR(bs.predicted_decrease, predicted, 1e-9 * std::abs(predicted));
  }
}

TEST(SchurSystem, UndampedReducedMatrixIsTheInverseMarginalCovariance) {
  using enum FreeParam;
  FreeSet free;
  for (FreeParam p : {psi, phi, f, y0}) free.add(p);
  RandomProblem p(12, free, 2, 9);
  const int n = p.layout.size();
  const Eigen::MatrixXd J = p.full_jacobian();
  const Eigen::MatrixXd cov = (J.transpose() * J).inverse();
  ReducedMatrix Nr;
  ReducedVector g;
  build_reduced_system(p.layout, p.state, 0.0, Nr, g);
  const Eigen::MatrixXd marginal = Eigen::MatrixXd(Nr).inverse();
  EXPECT_LT((marginal - cov.topLeftCorner(n, n)).norm(), 1e-9 * cov.topLeftCorner(n, n).norm());
}

TEST(SchurSystem, APickWhoseXMovesNothingCannotBeEliminated) {
  PickRows rows(2);
  rows.set(0, Vec2(1.0, 2.0), PickJacobian::Ones(), Vec2(0.3, -0.1), 2);
  rows.set(1, Vec2(1.0, 2.0), PickJacobian::Ones(), Vec2::Zero(), 2);
  EXPECT_TRUE(rows.complete(1));
  EXPECT_FALSE(rows.complete(2));
}

TEST(SchurSystemDeathTest, LayoutWithNothingFreeIsACallersBug) {
  // The solver refuses such a request (invalid_input) before any reduced system is built;
  // reaching here with one stops the program instead of running a kernel of another size.
  const ParameterLayout nothing_free(FreeSet{}, 2);
  PickRows rows(4);
  SolverState state;
  state.rows = &rows;
  const LineSegments segments;
  ReducedMatrix N;
  ReducedVector g;
  EXPECT_DEATH(accumulate_normals(nothing_free, segments, state), "");
  EXPECT_DEATH(build_reduced_system(nothing_free, state, 0.0, N, g), "");
}

}  // namespace
}  // namespace ccdlane::solver
