// Paper mode (docs/solver.md): the seed paper's algebraic collinearity residuals r1, r2 (mm^2)
// of lens, cell centre and road point, with each x_i at its closed-form optimum.
#pragma once

#include <span>

#include "core/solver/parameter_layout.hpp"
#include "core/solver/solver_state.hpp"

namespace ccdlane::solver {

class PaperResidual {
 public:
  // First lambda from a cold start (LmOptions). The algebraic residuals are products of
  // unknowns, and the index has spurious minima (toward yaw +-90 degrees the rays' x
  // extent, and with it every residual, shrinks): a near Gauss-Newton first step from a
  // cold start can land in one, so start well damped.
  static constexpr double kColdInitialDamping = 1.0;

  explicit PaperResidual(const CameraSpec& spec) : camera_(spec, CameraPose{}) {}

  // `ideal_px` holds each pick's undistorted pixel (pose-independent, computed once).
  void configure(const ParameterLayout& layout, std::span<const Pick> picks, std::span<const Vec2> ideal_px) {
    layout_ = &layout;
    picks_ = picks;
    ideal_px_ = ideal_px;
  }

  // Moves every x_i of `state` to the minimiser of r1^2 + r2^2 at the state's pose and
  // lines (variable projection: the cost is then a function of the globals and lines
  // alone), then fills residuals, Jacobians and J. False when some pick cannot be
  // eliminated (PickRows::complete).
  bool evaluate(SolverState& state);
  // The LM loop's two stages; the paper's residuals are cheap, so the first does all.
  bool evaluate_cost(SolverState& state) { return evaluate(state); }
  bool evaluate_jacobians(SolverState&) { return true; }

 private:
  CameraModel camera_;
  const ParameterLayout* layout_ = nullptr;
  std::span<const Pick> picks_;
  std::span<const Vec2> ideal_px_;
};

// argmin over x of r1^2 + r2^2, for r1 = a1 x + b1 - q x^2 and r2 = a2 x + b2: closed
// form when q = 0 (both residuals linear), else Newton steps from the linear solution.
double paper_optimal_x(double a1, double b1, double q, double a2, double b2);

}  // namespace ccdlane::solver
