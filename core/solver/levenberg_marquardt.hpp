// The Levenberg-Marquardt loop of the lane solver, a template over the residual model
// (reprojection or paper), with x_i eliminated by the Schur complement each iteration.
// Every workspace is passed in, preallocated: nothing here allocates or throws.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "core/solver/cholesky.hpp"
#include "core/solver/nielsen_damping.hpp"
#include "core/solver/schur_system.hpp"

namespace ccdlane::solver {

struct LmWorkspace {
  explicit LmWorkspace(int max_picks) : dx(static_cast<std::size_t>(max_picks)) {}
  ReducedMatrix N, A;
  ReducedVector g, step;
  std::vector<double> dx;  // per pick
};

struct LmOptions {
  int max_iterations = 50;
  // The first lambda, relative to the normal matrix's diagonal: Madsen, Nielsen & Tingleff's tau
  // ("Methods for non-linear least squares problems", 2004): 1e-6 when the start is
  // believed good (a warm start), 1e-3 or even 1 otherwise.
  double initial_damping = 1e-3;
};

struct LmOutcome {
  SolveStatus status = SolveStatus::max_iterations;
  int iterations = 0;
};

// Stopping rules of docs/solver.md.
constexpr double kCostTolerance = 1e-12;  // |J - J_new| <= tol * J
constexpr double kStepTolerance = 1e-12;  // |step| <= tol * (|parameters| + tol), x_i included

// The linearisation of an evaluated state: its Jacobians, summed into its normals. False
// when the Jacobians cannot be had (the model says why).
template <class Model>
bool linearise(Model& model, const ParameterLayout& layout, const LineSegments& segments, SolverState& state) {
  if (!model.evaluate_jacobians(state)) return false;
  accumulate_normals(layout, segments, state);
  return true;
}

// Marquardt's scale-invariant damping, N + lambda diag(N) (the same step as lambda added
// to the system scaled to unit diagonal, without the scaling's square roots), with
// Nielsen's update of lambda from the gain ratio. `current`
// holds an evaluated, linearised state on entry and the best state on return (still
// linearised, for the covariance); `candidate` is scratch. The picks are sorted by line
// (`segments`).
// Model: bool evaluate_cost(SolverState&) filling residuals, priors and cost (and, for
// variable projection, x), then bool evaluate_jacobians(SolverState&) for the same state
// (false when they cannot be had): Jacobians are computed only for steps that are taken.
template <class Model>
LmOutcome levenberg_marquardt(Model& model, const ParameterLayout& layout, const LineSegments& segments, int num_picks,
                              const LmOptions& options, SolverState*& current, SolverState*& candidate,
                              LmWorkspace& ws) {
  LmOutcome out;
  const int n = layout.size();
  NielsenDamping damping{options.initial_damping};
  double& lambda = damping.lambda;
  const auto reject = [&] { damping.reject(); };
  if (current->cost == 0.0) {  // nothing left to decrease: an exact fit
    out.status = SolveStatus::converged_cost;
    return out;
  }
  while (out.iterations < options.max_iterations) {
    ++out.iterations;
    build_reduced_system(layout, *current, lambda, ws.N, ws.g);
    ws.A = ws.N;
    // A parameter nothing depends on has a zero diagonal: damp it as a unit one.
    for (int c = 0; c < n; ++c) ws.A(c, c) += lambda * (ws.N(c, c) > 0.0 ? ws.N(c, c) : 1.0);
    // Positive definite whenever lambda > 0 (and N is semi-definite).
    ws.step = -ws.g;
    const bool factored = cholesky_solve(ws.A, ws.step);
    if (!factored || !ws.step.allFinite()) {
      if (!(lambda < 1e30)) {
        out.status = SolveStatus::numerical_failure;
        return out;
      }
      reject();
      continue;
    }
    const BackSubstitution bs = back_substitute(layout, segments, *current, lambda, ws.step, ws.dx.data());

    const double x_norm2 = Eigen::Map<const Eigen::ArrayXd>(current->x, num_picks).square().sum();  // vectorised
    const double step_norm = std::sqrt(ws.step.squaredNorm() + bs.x_step_squared_norm);
    const double param_norm = std::sqrt(layout.squared_norm(current->pose, current->lines.data()) + x_norm2);
    if (step_norm <= kStepTolerance * (param_norm + kStepTolerance)) {
      out.status = SolveStatus::converged_step;
      return out;
    }

    candidate->pose = current->pose;
    candidate->lines = current->lines;
    layout.apply_step(ws.step, candidate->pose, candidate->lines.data());
    const auto picks_x = [num_picks](double* x) { return Eigen::Map<Eigen::ArrayXd>(x, num_picks); };
    picks_x(candidate->x) = picks_x(current->x) + picks_x(ws.dx.data());
    if (!model.evaluate_cost(*candidate) || !std::isfinite(candidate->cost)) {
      reject();
      continue;
    }
    const double decrease = current->cost - candidate->cost;
    if (std::abs(decrease) <= kCostTolerance * current->cost) {
      // Converged: the current point is the optimum to within the rule, and its
      // Jacobians (for the covariance) are at hand.
      out.status = SolveStatus::converged_cost;
      return out;
    }
    const double rho = bs.predicted_decrease > 0.0 ? decrease / bs.predicted_decrease : -1.0;
    if (rho > 0.0) {
      if (!linearise(model, layout, segments, *candidate)) {
        reject();
        continue;
      }
      std::swap(current, candidate);
      damping.accept(rho);
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
