// Reprojection mode (docs/solver.md): pixel residuals of each pick's road point, whitened by
// the pick noise, with analytic Jacobians over the free globals, its line and its x,
// evaluated over all picks at once (RoadProjection).
#pragma once

#include <span>

#include "core/solver/parameter_layout.hpp"
#include "core/solver/road_projection.hpp"
#include "core/solver/solver_state.hpp"

namespace ccdlane::solver {

class ReprojectionResidual {
 public:
  using Array = Eigen::ArrayXd;

  // First lambda from a cold start (LmOptions): the usual 1e-3 of the unit diagonal.
  static constexpr double kColdInitialDamping = 1e-3;

  ReprojectionResidual(const CameraSpec& spec, int max_picks);

  // `picks` sorted by line (`segments`).
  void configure(const ParameterLayout& layout, const LineSegments& segments, std::span<const Pick> picks,
                 double pixel_sigma, const SolverPriors& priors);

  // Residuals and cost J at `state` (its x are kept). False when some road point cannot
  // be seen (behind the lens or beyond the distortion model's field).
  bool evaluate_cost(SolverState& state);
  // The Jacobians' rows at the state last given to evaluate_cost. False when some pick
  // cannot be eliminated (PickRows::complete).
  bool evaluate_jacobians(SolverState& state);
  bool evaluate(SolverState& state) { return evaluate_cost(state) && evaluate_jacobians(state); }

 private:
  RoadProjection projection_;
  const ParameterLayout* layout_ = nullptr;
  const LineSegments* segments_ = nullptr;
  std::span<const Pick> picks_;
  double inv_sigma_ = 1.0;
  const SolverPriors* priors_ = nullptr;
  // Per pick, sized at construction: the observed pixel, the road point, its line's
  // slope there; the covectors of b_x and b_u (b_x turned).
  Array px_, py_, x_, y_, slope_;
  RoadProjection::Covectors seen_;
};

}  // namespace ccdlane::solver
