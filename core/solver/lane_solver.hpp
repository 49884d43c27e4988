// The lane problem of docs/solver.md: camera attitude, lane lines and every mark's position
// from labelled pixel picks, by an allocation-free Levenberg-Marquardt solve.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>

#include "core/geometry/camera_model.hpp"
#include "core/geometry/road_line.hpp"
#include "core/solver/solver_options.hpp"

namespace ccdlane {

// Compile-time bound on lines per problem. With every parameter free the reduced
// (dense) system then has at most 5 + 3 * 4 = 17 unknowns, whatever the number of picks
// (a shared curvature: 5 + 1 + 2 * 4 = 14).
constexpr int kMaxLaneLines = 4;
constexpr int kMaxReducedParams = kPoseParams + 3 * kMaxLaneLines;

// One pick: an observed (distorted) 1-based pixel of a mark on lane line `line`.
struct Pick {
  int line = 0;  // 0 .. num_lines-1
  double px = 0.0;
  double py = 0.0;
};

// The line's signed radius of curvature at x = 0, mm: positive when it bends toward +y
// (left), infinite when straight. (1 + m^2)^(3/2) / (2 c); about 1 / (2 c) for the
// small headings of a lane.
double radius_of_curvature_mm(const RoadLine& line);

// What one solve is asked to do. Fixed parameters keep their value from `initial_pose`
// and `initial_lines`. Beyond docs/solver.md's roll/offset family and scale (free H without a
// prior), note: a free heading m per line makes the lines' parallelism, and with it yaw
// and (for straight lines) pitch, undetermined. Such requests come back rank_deficient.
struct SolveRequest {
  SolverMode mode = SolverMode::reprojection;
  FreeSet free = SolverOptions::default_free();
  // shared_curvature: one c for every line (free; `free` must not hold c), started from
  // the mean c of initial_lines (0 when they are fitted), reported in each line's c_per_mm.
  LineModel line_model = LineModel::per_line;
  double pixel_sigma = 0.5;
  int max_iterations = 50;
  SolverPriors priors;
  CameraPose initial_pose;
  std::span<const Pick> picks;
  int num_lines = 0;
  // Initial lines (exactly num_lines of them); empty = a straight-line fit of the
  // initial ground points of each line (docs/solver.md): y0 and, when m is free, m from the
  // fit, otherwise m = 0; c = 0.
  std::span<const RoadLine> initial_lines;
  // The initial pose and lines are a solution of a similar problem (the previous frame):
  // Levenberg-Marquardt then starts close to Gauss-Newton and needs fewer iterations.
  bool warm_start = false;
};

enum class SolveStatus : std::uint8_t {
  converged_cost,     // relative cost decrease < 1e-12
  converged_step,     // relative step norm < 1e-12
  max_iterations,     // stopped without meeting a convergence rule
  invalid_input,      // NaN/inf, a line id out of range, too many picks or lines, nothing
                      // free, c free with a shared curvature
  too_few_picks,      // fewer residuals than unknowns
  no_ground_point,    // a pick's ray misses the road at the initial pose
  numerical_failure,  // the step could not be computed
};
const char* to_string(SolveStatus s);

// Sigma of a parameter: NaN when the parameter is fixed or not determined.
constexpr double kUndetermined = std::numeric_limits<double>::quiet_NaN();

struct SolveSigmas {
  double psi_deg = kUndetermined, theta_deg = kUndetermined, phi_deg = kUndetermined;
  double H_mm = kUndetermined, f_mm = kUndetermined;
  // A shared curvature's sigma stands in c_per_mm of every line.
  std::array<double, kMaxLaneLines> y0_mm, m, c_per_mm;  // filled with kUndetermined
  SolveSigmas();
};

// One unknown of the reduced (dense) system: a free global, or a free kind of one line.
struct ReducedParam {
  FreeParam kind = FreeParam::psi;
  int line = -1;  // the lane line for y0/m/c, -1 for globals and a shared curvature
};

using ReducedMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxReducedParams, kMaxReducedParams>;

struct SolveResult {
  SolveStatus status = SolveStatus::invalid_input;
  bool converged = false;       // a convergence rule fired (not max_iterations, not failure)
  bool rank_deficient = false;  // some free parameter is not determined by the data
  int iterations = 0;           // LM steps computed (accepted or not)
  double cost = 0.0;            // the mode's performance index J at the optimum
  double rms_px = 0.0;          // RMS over the picks of the reprojection distance, pixels
  CameraPose pose;
  int num_lines = 0;
  std::array<RoadLine, kMaxLaneLines> lines{};
  SolveSigmas sigma;
  // Evaluated mark positions, one per pick, valid until the next solve (solver storage).
  std::span<const Vec2> points_mm;
  // The pick behind a no_ground_point or invalid_input status (index into picks), or -1.
  int failed_pick = -1;
  // The free parameters in the order of `covariance`, and their covariance in internal
  // units (radians, mm) with NaN rows/columns for undetermined ones. Reprojection mode:
  // the inverse of the reduced normal matrix at the optimum. Paper mode (algebraic
  // residuals of unknown scale): that inverse times the residual variance estimate
  // J / (picks - unknowns), NaN when there are no spare picks.
  int num_free = 0;
  std::array<ReducedParam, kMaxReducedParams> free_params{};
  ReducedMatrix covariance;
};

// Residuals needed before a request is solvable (docs/solver.md: fewer residuals than
// unknowns is too_few_picks): the minimum number of picks for `request`'s free set,
// lines and priors. Each pick brings two residuals and one unknown (its x).
int required_picks(const SolveRequest& request);

class LaneSolver {
 public:
  // All workspaces are sized here; solve() never allocates. max_lines <= kMaxLaneLines.
  LaneSolver(const CameraSpec& camera, int max_picks, int max_lines = kMaxLaneLines);
  ~LaneSolver();
  LaneSolver(const LaneSolver&) = delete;
  LaneSolver& operator=(const LaneSolver&) = delete;

  // Solves; never throws. Warm start: pass the previous result's pose and lines as
  // request.initial_pose / initial_lines, with request.warm_start set.
  const SolveResult& solve(const SolveRequest& request);

  int max_picks() const;
  int max_lines() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ccdlane
