// What a lane solve may be asked to do, as the configuration's [solver] and [prior] tables
// map onto it: which unknowns are free, which residual form, and Gaussian priors.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace ccdlane {

// The unknowns a problem may leave free (docs/solver.md "Unknowns").
enum class FreeParam : std::uint8_t { psi, theta, phi, H, f, y0, m, c };
constexpr int kFreeParamCount = 8;

class FreeSet {
 public:
  constexpr FreeSet() = default;
  constexpr bool has(FreeParam p) const { return (bits_ >> static_cast<int>(p)) & 1u; }
  constexpr void add(FreeParam p) { bits_ |= static_cast<std::uint8_t>(1u << static_cast<int>(p)); }
  constexpr void remove(FreeParam p) { bits_ &= static_cast<std::uint8_t>(~(1u << static_cast<int>(p))); }
  constexpr bool empty() const { return bits_ == 0; }
  constexpr bool operator==(const FreeSet&) const = default;

 private:
  std::uint8_t bits_ = 0;
};

const char* free_param_name(FreeParam p);  // "psi", "theta", ...
std::optional<FreeParam> free_param_from_name(const std::string& name);

enum class SolverMode { reprojection, paper };

// How the lane lines bend (docs/geometry.md: y = y0_j + m_j x + c_j x^2).
enum class LineModel : std::uint8_t {
  // Each line its own y0, m and c, each kind free or fixed as the free set says: with c
  // fixed (the default free set, and fitted lines start at c = 0) the seed paper's
  // straight lines. Config: line_model = "straight".
  per_line,
  // The lines of one road are parallel curves: one curvature c shared by every line of
  // the frame, always free; y0 and m per line as the free set says (which must not hold
  // c). A straight model on a bend biases yaw by about c (x_near + x_far); this one does
  // not. c needs marks at three or more distances. Config: line_model = "curved".
  shared_curvature,
};

// A Gaussian prior N(mean, sigma^2) on one quantity, in the interface's units.
struct Prior {
  double mean = 0.0;
  double sigma = 0.0;

  bool operator==(const Prior&) const = default;
};

// Priors in interface units (degrees, mm); empty = none. Gyro roll/pitch arrive here.
// Used in reprojection mode only: the paper's index takes no priors (docs/solver.md). A
// lane-width prior needs at least two lines and is ignored with fewer.
struct SolverPriors {
  std::optional<Prior> psi_deg, theta_deg, phi_deg, H_mm, f_mm, lane_width_mm;
  // The two lines (indices into the request's lines) whose offsets differ by
  // lane_width_mm; -1: the outermost two at each evaluation. A caller who knows which
  // lines bound one lane names them: beside a shoulder or a barrier's foot the outermost
  // lines are not a whole number of lanes apart, and with roll free (no gyro) the prior
  // would tilt the camera to make them so.
  int lane_width_left = -1, lane_width_right = -1;

  bool operator==(const SolverPriors&) const = default;
};

// How every solve of a run is set up ([solver]).
struct SolverOptions {
  SolverMode mode = SolverMode::reprojection;
  FreeSet free = default_free();
  LineModel line_model = LineModel::shared_curvature;  // [solver] line_model = "curved" (README)
  double pixel_sigma = 0.5;
  int max_iterations = 50;

  // psi, theta, phi and each line's y0: the camera's attitude and the lines' offsets.
  static FreeSet default_free();
  bool operator==(const SolverOptions&) const = default;
};

}  // namespace ccdlane
