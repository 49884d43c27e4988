// Prior residuals: angles are compared in degrees, as they are configured.
#include "core/solver/prior_residuals.hpp"

#include <utility>

namespace ccdlane::solver {
namespace {

// Appends r = (value - mean) / sigma with d r / d(value) = gain / sigma at `index`.
void add_row(PriorRows& rows, const Prior& prior, double value, int index, double gain, double& cost) {
  PriorRow& row = rows.rows[rows.count++];
  row.r = (value - prior.mean) / prior.sigma;
  row.size = 0;
  row.add(index, gain / prior.sigma);
  cost += row.r * row.r;
}

// The lines with the largest and the smallest y0, whose difference is the lane width.
std::pair<int, int> outermost_lines(const RoadLine* lines, int num_lines) {
  int left = 0, right = 0;
  for (int j = 1; j < num_lines; ++j) {
    if (lines[j].y0_mm > lines[left].y0_mm) left = j;
    if (lines[j].y0_mm < lines[right].y0_mm) right = j;
  }
  return {left, right};
}

}  // namespace

void evaluate_priors(const SolverPriors& priors, const ParameterLayout& layout, const CameraPose& pose,
                     const RoadLine* lines, PriorRows& rows, double& cost) {
  rows.count = 0;
  const double per_rad = rad_to_deg(1.0);
  if (priors.psi_deg)
    add_row(rows, *priors.psi_deg, rad_to_deg(pose.attitude.psi), layout.global_index(kPsi), per_rad, cost);
  if (priors.theta_deg)
    add_row(rows, *priors.theta_deg, rad_to_deg(pose.attitude.theta), layout.global_index(kTheta), per_rad, cost);
  if (priors.phi_deg)
    add_row(rows, *priors.phi_deg, rad_to_deg(pose.attitude.phi), layout.global_index(kPhi), per_rad, cost);
  if (priors.H_mm) add_row(rows, *priors.H_mm, pose.H_mm, layout.global_index(kHeight), 1.0, cost);
  if (priors.f_mm) add_row(rows, *priors.f_mm, pose.f_mm, layout.global_index(kFocal), 1.0, cost);
  if (priors.lane_width_mm && layout.num_lines() >= 2) {
    const bool named = priors.lane_width_left >= 0 && priors.lane_width_left < layout.num_lines() &&
                       priors.lane_width_right >= 0 && priors.lane_width_right < layout.num_lines();
    const auto [left, right] = named ? std::pair{priors.lane_width_left, priors.lane_width_right}
                                     : outermost_lines(lines, layout.num_lines());
    add_row(rows, *priors.lane_width_mm, lines[left].y0_mm - lines[right].y0_mm, layout.line_index(left, kY0), 1.0,
            cost);
    // The right-hand line enters with the opposite sign (a no-op when y0 is fixed).
    PriorRow& row = rows.rows[rows.count - 1];
    if (left != right) row.add(layout.line_index(right, kY0), -1.0 / priors.lane_width_mm->sigma);
  }
}

int count_free_priors(const SolverPriors& priors, const ParameterLayout& layout) {
  int n = 0;
  n += priors.psi_deg && layout.global_index(kPsi) >= 0;
  n += priors.theta_deg && layout.global_index(kTheta) >= 0;
  n += priors.phi_deg && layout.global_index(kPhi) >= 0;
  n += priors.H_mm && layout.global_index(kHeight) >= 0;
  n += priors.f_mm && layout.global_index(kFocal) >= 0;
  n += priors.lane_width_mm && layout.num_lines() >= 2 && layout.line_index(0, kY0) >= 0;
  return n;
}

}  // namespace ccdlane::solver
