// Reprojection mode (solver.md): pixel residuals of each pick's road point, whitened by
// the pick noise, with analytic Jacobians over the free globals, its line and its x.
#pragma once

#include <span>

#include "core/solver/parameter_layout.hpp"
#include "core/solver/solver_state.hpp"

namespace ccdlane::solver {

class ReprojectionResidual {
 public:
  // Pixel residuals are close to linear over a frame-to-frame change: start near
  // Gauss-Newton (Marquardt's usual 1e-3 of the unit diagonal).
  static constexpr double kInitialDamping = 1e-3;

  explicit ReprojectionResidual(const CameraSpec& spec) : camera_(spec, CameraPose{}) {}

  void configure(const ParameterLayout& layout, std::span<const Pick> picks, double pixel_sigma,
                 const SolverPriors& priors) {
    layout_ = &layout;
    picks_ = picks;
    inv_sigma_ = 1.0 / pixel_sigma;
    priors_ = &priors;
  }

  // Residuals, Jacobians and cost J at `state` (its x are kept). False when some road
  // point cannot be seen (behind the lens or beyond the distortion model's field).
  bool evaluate(SolverState& state);

 private:
  CameraModel camera_;
  const ParameterLayout* layout_ = nullptr;
  std::span<const Pick> picks_;
  double inv_sigma_ = 1.0;
  const SolverPriors* priors_ = nullptr;
};

}  // namespace ccdlane::solver
