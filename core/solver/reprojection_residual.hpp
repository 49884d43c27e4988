// Reprojection mode (solver.md): pixel residuals of each pick's road point, whitened by
// the pick noise, with analytic Jacobians over the free globals, its line and its x.
#pragma once

#include <span>
#include <vector>

#include "core/solver/parameter_layout.hpp"
#include "core/solver/road_projection.hpp"
#include "core/solver/solver_state.hpp"

namespace ccdlane::solver {

class ReprojectionResidual {
 public:
  // First lambda from a cold start (LmOptions): the usual 1e-3 of the unit diagonal.
  static constexpr double kColdInitialDamping = 1e-3;

  ReprojectionResidual(const CameraSpec& spec, int max_picks)
      : camera_(spec, CameraPose{}), chains_(static_cast<std::size_t>(max_picks)) {}

  void configure(const ParameterLayout& layout, std::span<const Pick> picks, double pixel_sigma,
                 const SolverPriors& priors) {
    layout_ = &layout;
    picks_ = picks;
    inv_sigma_ = 1.0 / pixel_sigma;
    priors_ = &priors;
  }

  // Residuals and cost J at `state` (its x are kept). False when some road point cannot
  // be seen (behind the lens or beyond the distortion model's field).
  bool evaluate_cost(SolverState& state);
  // The Jacobians at the state last given to evaluate_cost (from its stored chains).
  void evaluate_jacobians(SolverState& state);
  bool evaluate(SolverState& state) {
    if (!evaluate_cost(state)) return false;
    evaluate_jacobians(state);
    return true;
  }

 private:
  CameraModel camera_;
  RoadProjection projection_;
  std::vector<RoadProjection::Chain> chains_;  // per pick, sized at construction
  const ParameterLayout* layout_ = nullptr;
  std::span<const Pick> picks_;
  double inv_sigma_ = 1.0;
  const SolverPriors* priors_ = nullptr;
};

}  // namespace ccdlane::solver
