// Reprojection residuals: r = (pi(X_i) - p_i) / sigma_px with X_i = (x_i, y_j(x_i), 0).
#include "core/solver/reprojection_residual.hpp"

#include "core/solver/prior_residuals.hpp"

namespace ccdlane::solver {

bool ReprojectionResidual::evaluate_cost(SolverState& state) {
  camera_.set_pose(state.pose);
  projection_.set_camera(camera_);
  // The division/square-root chains of the picks are independent: this loop overlaps
  // them in the pipeline, and evaluate_jacobians reuses them.
  double cost = 0.0;
  for (std::size_t i = 0; i < picks_.size(); ++i) {
    const Pick& pick = picks_[i];
    const double x = state.x[i];
    if (!projection_.start(x, line_y(state.lines[pick.line], x), chains_[i])) return false;
    PickBlock& b = state.blocks[i];
    b.r = (projection_.pixel(chains_[i]) - Vec2(pick.px, pick.py)) * inv_sigma_;
    cost += b.r.squaredNorm();
  }
  evaluate_priors(*priors_, *layout_, state.pose, state.lines.data(), state.priors, cost);
  state.cost = cost;
  return true;
}

void ReprojectionResidual::evaluate_jacobians(SolverState& state) {
  const ParameterLayout& layout = *layout_;
  const int ng = layout.num_global(), nk = layout.num_line_kinds();
  RoadProjection::Derivatives d;
  for (std::size_t i = 0; i < picks_.size(); ++i) {
    const LaneLine& line = state.lines[picks_[i].line];
    const double x = state.x[i];
    projection_.derivatives(chains_[i], d);
    PickBlock& b = state.blocks[i];
    for (int k = 0; k < ng; ++k) b.J.col(k) = projection_.pose_column(d, layout.global(k)) * inv_sigma_;
    // The road point moves sideways (fixed-frame y) with y0, m and c; along the line with x.
    const Vec2 d_side = projection_.road_column(d, 1) * inv_sigma_;
    const double basis[kLineParams] = {1.0, x, x * x};
    for (int k = 0; k < nk; ++k) b.J.col(ng + k) = d_side * basis[layout.line_kind(k)];
    b.J.rightCols(kMaxLocalParams - ng - nk).setZero();
    b.Jx = projection_.road_column(d, 0) * inv_sigma_ + d_side * (line.m + 2.0 * line.c_per_mm * x);
  }
}

}  // namespace ccdlane::solver
