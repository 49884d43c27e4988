// One point of the LM iteration: the parameters, every pick's x, and their linearisation.
#pragma once

#include <array>

#include "core/solver/solver_types.hpp"

namespace ccdlane::solver {

// Views into the solver's preallocated per-pick storage; two of these (current and
// candidate) are swapped by pointer, never copied, as the iteration goes on.
struct SolverState {
  CameraPose pose;
  std::array<RoadLine, kMaxLaneLines> lines{};
  double* x = nullptr;       // per pick: its distance ahead along its line, mm
  PickRows* rows = nullptr;  // per pick: residuals and Jacobians at this point
  LineNormals normals;       // the rows' sums per line (accumulate_normals)
  PriorRows priors;
  double cost = 0.0;
};

// The road point of a pick at distance x along `line`.
inline double line_y(const RoadLine& line, double x) { return line.y0_mm + (line.m + line.c_per_mm * x) * x; }

}  // namespace ccdlane::solver
