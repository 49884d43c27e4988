// The Gaussian priors of reprojection mode (docs/solver.md) as whitened residual rows.
#pragma once

#include "core/solver/parameter_layout.hpp"

namespace ccdlane::solver {

// One row per configured prior: r = (q - mean) / sigma in interface units (degrees, mm),
// with its derivative over the reduced parameters (zero for fixed ones). Adds r^2 to
// `cost`. The lane width is y0_max - y0_min over the lines (ignored below two lines).
void evaluate_priors(const SolverPriors& priors, const ParameterLayout& layout, const CameraPose& pose,
                     const RoadLine* lines, PriorRows& rows, double& cost);

// How many priors constrain a free parameter: each is one more residual.
int count_free_priors(const SolverPriors& priors, const ParameterLayout& layout);

}  // namespace ccdlane::solver
