// The lane problem of solver.md: camera attitude, lane lines and every mark's position
// from labelled pixel picks, by an allocation-free Levenberg-Marquardt solve.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>

#include "core/config/config.hpp"
#include "core/geometry/camera_model.hpp"

namespace ccdlane {

constexpr int kMaxLaneLines = 8;  // compile-time bound on lines per problem

// One pick: an observed (distorted) 1-based pixel of a mark on lane line `line`.
struct Pick {
  int line = 0;  // 0 .. num_lines-1
  double px = 0.0;
  double py = 0.0;
};

// A lane line on the road: y = y0 + m x + c x^2 (fixed frame, mm).
struct LaneLine {
  double y0_mm = 0.0;
  double m = 0.0;
  double c_per_mm = 0.0;
};

// Priors in interface units (degrees, mm); empty = none. Gyro roll/pitch arrive here.
struct SolverPriors {
  std::optional<Prior> psi_deg, theta_deg, phi_deg, H_mm, f_mm, lane_width_mm;
};

// What one solve is asked to do. Fixed parameters keep their value from `initial_pose`
// and `initial_lines`.
struct SolveRequest {
  SolverMode mode = SolverMode::reprojection;
  FreeSet free = SolverConfig::default_free();
  double pixel_sigma = 0.5;
  int max_iterations = 50;
  SolverPriors priors;
  CameraPose initial_pose;
  std::span<const Pick> picks;
  int num_lines = 0;
  // Initial lines; empty = a straight-line fit of the initial ground points (solver.md).
  std::span<const LaneLine> initial_lines;
};

enum class SolveStatus : std::uint8_t {
  converged_cost,       // relative cost decrease < 1e-12
  converged_step,       // relative step norm < 1e-12
  max_iterations,       // stopped without meeting a convergence rule
  invalid_input,        // NaN/inf, a line id out of range, too many picks or lines
  too_few_picks,        // fewer residuals than unknowns
  no_ground_point,      // a pick's ray misses the road at the initial pose
  numerical_failure,    // the step could not be computed
};
const char* to_string(SolveStatus s);

// Sigma of a parameter: NaN when the parameter is fixed or not determined.
constexpr double kUndetermined = std::numeric_limits<double>::quiet_NaN();

struct SolveSigmas {
  double psi_deg = kUndetermined, theta_deg = kUndetermined, phi_deg = kUndetermined;
  double H_mm = kUndetermined, f_mm = kUndetermined;
  std::array<double, kMaxLaneLines> y0_mm, m, c_per_mm;  // filled with kUndetermined
};

struct SolveResult {
  SolveStatus status = SolveStatus::invalid_input;
  bool converged = false;       // a convergence rule fired (not max_iterations, not failure)
  bool rank_deficient = false;  // some free parameter is not determined by the data
  int iterations = 0;
  double cost = 0.0;            // the mode's performance index J at the optimum
  double rms_px = 0.0;          // reprojection RMS over the picks, pixels
  CameraPose pose;
  int num_lines = 0;
  std::array<LaneLine, kMaxLaneLines> lines{};
  SolveSigmas sigma;
  // Evaluated mark positions, one per pick, valid until the next solve (solver storage).
  std::span<const Vec2> points_mm;
};

class LaneSolver {
 public:
  // All workspaces are sized here; solve() never allocates.
  LaneSolver(const CameraSpec& camera, int max_picks, int max_lines = kMaxLaneLines);
  ~LaneSolver();
  LaneSolver(const LaneSolver&) = delete;
  LaneSolver& operator=(const LaneSolver&) = delete;

  // Solves; never throws. Warm start: pass the previous result's pose and lines as
  // request.initial_pose / initial_lines.
  const SolveResult& solve(const SolveRequest& request);

  int max_picks() const;
};

}  // namespace ccdlane
