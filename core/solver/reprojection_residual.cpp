// Reprojection residuals: r = (pi(X_i) - p_i) / sigma_px with X_i = (x_i, y_j(x_i), 0).
#include "core/solver/reprojection_residual.hpp"

#include "core/solver/prior_residuals.hpp"

namespace ccdlane::solver {

ReprojectionResidual::ReprojectionResidual(const CameraSpec& spec, int max_picks)
    : projection_(spec, max_picks), seen_(max_picks) {
  for (Array* a : {&px_, &py_, &x_, &y_, &slope_}) a->setZero(max_picks);
}

void ReprojectionResidual::configure(const ParameterLayout& layout, const LineSegments& segments,
                                     std::span<const Pick> picks, double pixel_sigma, const SolverPriors& priors) {
  layout_ = &layout;
  segments_ = &segments;
  projection_.forget_pose();
  picks_ = picks;
  inv_sigma_ = 1.0 / pixel_sigma;
  priors_ = &priors;
  for (std::size_t i = 0; i < picks.size(); ++i) {
    px_[i] = picks[i].px;
    py_[i] = picks[i].py;
  }
}

bool ReprojectionResidual::evaluate_cost(SolverState& state) {
  const int n = static_cast<int>(picks_.size());
  projection_.set_pose(state.pose);
  for (int j = 0; j < layout_->num_lines(); ++j) {  // each pick's road point, on its own line
    const RoadLine line = state.lines[j];
    const int end = segments_->begin[j + 1];
    for (int i = segments_->begin[j]; i < end; ++i) {
      const double x = state.x[i];
      x_[i] = x;
      y_[i] = line_y(line, x);
      slope_[i] = line.m + 2.0 * line.c_per_mm * x;
    }
  }
  if (!projection_.project(x_, y_, n)) return false;
  PickRows& rows = *state.rows;
  rows.r0.head(n) = (projection_.u().head(n) - px_.head(n)) * inv_sigma_;
  rows.r1.head(n) = (projection_.v().head(n) - py_.head(n)) * inv_sigma_;
  double cost = (rows.r0.head(n).square() + rows.r1.head(n).square()).sum();
  evaluate_priors(*priors_, *layout_, state.pose, state.lines.data(), state.priors, cost);
  state.cost = cost;
  return true;
}

bool ReprojectionResidual::evaluate_jacobians(SolverState& state) {
  const ParameterLayout& layout = *layout_;
  const int n = static_cast<int>(picks_.size()), ng = layout.num_global(), shared_c = layout.shared_curvature_index();
  PickRows& rows = *state.rows;
  // Along the line: the road point moves along x and sideways with the line's slope.
  projection_.differentiate(slope_, inv_sigma_, n, rows.jx0, rows.jx1);
  if (!rows.complete(n)) return false;
  // Every column seen along b_x = Jx and b_u = Jx turned (PickRows), from their covectors.
  projection_.pull_back(rows.jx0, rows.jx1, inv_sigma_, n, seen_);
  for (int k = 0; k < layout.num_pose(); ++k)
    projection_.pose_along(seen_, layout.global(k), n, rows.ax[k], rows.au[k]);
  // y0, m and c move the road point sideways by 1, x and x^2; a shared c moves every
  // line's as its own c would.
  if (shared_c >= 0) {
    projection_.road_along(seen_, 1, n, rows.ax[shared_c], rows.au[shared_c]);
    rows.au[shared_c].head(n) *= x_.head(n).square();
    rows.ax[shared_c].head(n) *= x_.head(n).square();
  }
  for (int k = 0; k < layout.num_line_kinds(); ++k) {
    const int col = ng + k;
    projection_.road_along(seen_, 1, n, rows.ax[col], rows.au[col]);
    switch (layout.line_kind(k)) {
      case kY0: break;
      case kSlope:
        rows.au[col].head(n) *= x_.head(n);
        rows.ax[col].head(n) *= x_.head(n);
        break;
      default: rows.au[col].head(n) *= x_.head(n).square(); rows.ax[col].head(n) *= x_.head(n).square();
    }
  }
  return true;
}

}  // namespace ccdlane::solver
