// The reduced normal equations of the lane problem: every pick's x_i eliminated by the
// Schur complement of its 1x1 block, so the dense system has only the global and line
// unknowns and building it costs O(picks), once per linearisation.
#pragma once

#include "core/solver/parameter_layout.hpp"
#include "core/solver/solver_state.hpp"

namespace ccdlane::solver {

// Sums the picks' rows of `state` (sorted by line: `segments`) into state.normals.
void accumulate_normals(const ParameterLayout& layout, const LineSegments& segments, SolverState& state);

// N and g of the Gauss-Newton system N step = -g over the reduced parameters, from
// state.normals and state.priors, with each x_i's own curvature damped by (1 + lambda)
// as Levenberg-Marquardt damps every unknown (lambda = 0: the exact Schur complement,
// whose inverse is the parameters' marginal covariance). Priors enter as dense rows.
void build_reduced_system(const ParameterLayout& layout, const SolverState& state, double lambda, ReducedMatrix& N,
                          ReducedVector& g);

struct BackSubstitution {
  double predicted_decrease = 0.0;  // J - J_linearised(step): what the model promises
  double x_step_squared_norm = 0.0;
};

// The x_i steps that go with a reduced step (into dx), and the cost decrease the
// linearised problem predicts for the whole step.
BackSubstitution back_substitute(const ParameterLayout& layout, const LineSegments& segments, const SolverState& state,
                                 double lambda, const ReducedVector& step, double* dx);

}  // namespace ccdlane::solver
