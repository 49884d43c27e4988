// The Levenberg-Marquardt loop of the lane solver, a template over the residual model
// (reprojection or paper), with x_i eliminated by the Schur complement each iteration.
// Every workspace is passed in, preallocated: nothing here allocates or throws.
#pragma once

#include <cmath>
#include <span>
#include <utility>

#include <Eigen/Cholesky>

#include "core/solver/schur_system.hpp"

namespace ccdlane::solver {

struct LmWorkspace {
  ReducedMatrix N, A;
  ReducedVector g, scale, step;
  Eigen::LDLT<ReducedMatrix> ldlt{kMaxReducedParams};
  double* dx = nullptr;  // per pick
};

struct LmOutcome {
  SolveStatus status = SolveStatus::max_iterations;
  int iterations = 0;
};

// Stopping rules of solver.md.
constexpr double kCostTolerance = 1e-12;  // |J - J_new| <= tol * J
constexpr double kStepTolerance = 1e-12;  // |step| <= tol * (|parameters| + tol), x_i included

// Marquardt's scale-invariant damping: the reduced system is scaled to unit diagonal and
// lambda added to it, with Nielsen's update of lambda from the gain ratio. `current`
// holds an evaluated state on entry and the best state on return; `candidate` is scratch.
// Model: bool evaluate(SolverState&) filling blocks, priors and cost (and, for variable
// projection, x); kInitialDamping, the first lambda.
template <class Model>
LmOutcome levenberg_marquardt(Model& model, const ParameterLayout& layout, std::span<const Pick> picks,
                              int max_iterations, SolverState*& current, SolverState*& candidate, LmWorkspace& ws) {
  LmOutcome out;
  const int n = layout.size();
  const std::size_t num_picks = picks.size();
  double lambda = Model::kInitialDamping, nu = 2.0;
  ws.scale.setOnes(n);
  const auto reject = [&] {
    lambda *= nu;
    nu *= 2.0;
  };
  if (current->cost == 0.0) {  // nothing left to decrease: an exact fit
    out.status = SolveStatus::converged_cost;
    return out;
  }
  while (out.iterations < max_iterations) {
    ++out.iterations;
    build_reduced_system(layout, picks, *current, lambda, ws.N, ws.g);
    for (int k = 0; k < n; ++k) ws.scale[k] = ws.N(k, k) > 0.0 ? 1.0 / std::sqrt(ws.N(k, k)) : 1.0;
    ws.A = ws.scale.asDiagonal() * ws.N * ws.scale.asDiagonal();
    ws.A.diagonal().array() += lambda;
    ws.ldlt.compute(ws.A);
    ws.step = -ws.ldlt.solve(ws.scale.cwiseProduct(ws.g));
    ws.step.array() *= ws.scale.array();
    if (ws.ldlt.info() != Eigen::Success || !ws.step.allFinite()) {
      if (!(lambda < 1e30)) {
        out.status = SolveStatus::numerical_failure;
        return out;
      }
      reject();
      continue;
    }
    const BackSubstitution bs = back_substitute(layout, picks, *current, lambda, ws.step, ws.dx);

    double x_norm2 = 0.0;
    for (std::size_t i = 0; i < num_picks; ++i) x_norm2 += current->x[i] * current->x[i];
    const double step_norm = std::sqrt(ws.step.squaredNorm() + bs.x_step_squared_norm);
    const double param_norm = std::sqrt(layout.squared_norm(current->pose, current->lines.data()) + x_norm2);
    if (step_norm <= kStepTolerance * (param_norm + kStepTolerance)) {
      out.status = SolveStatus::converged_step;
      return out;
    }

    candidate->pose = current->pose;
    candidate->lines = current->lines;
    layout.apply_step(ws.step, candidate->pose, candidate->lines.data());
    for (std::size_t i = 0; i < num_picks; ++i) candidate->x[i] = current->x[i] + ws.dx[i];
    if (!model.evaluate(*candidate) || !std::isfinite(candidate->cost)) {
      reject();
      continue;
    }
    const double decrease = current->cost - candidate->cost;
    if (std::abs(decrease) <= kCostTolerance * current->cost) {
      if (decrease > 0.0) std::swap(current, candidate);
      out.status = SolveStatus::converged_cost;
      return out;
    }
    const double rho = bs.predicted_decrease > 0.0 ? decrease / bs.predicted_decrease : -1.0;
    if (rho > 0.0) {
      std::swap(current, candidate);
      const double t = 2.0 * rho - 1.0;
      lambda *= std::max(1.0 / 3.0, 1.0 - t * t * t);
      nu = 2.0;
      if (current->cost == 0.0) {
        out.status = SolveStatus::converged_cost;
        return out;
      }
    } else {
      reject();
    }
  }
  out.status = SolveStatus::max_iterations;
  return out;
}

}  // namespace ccdlane::solver
