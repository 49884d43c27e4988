// Reprojection residuals: r = (pi(X_i) - p_i) / sigma_px with X_i = (x_i, y_j(x_i), 0).
#include "core/solver/reprojection_residual.hpp"

#include "core/solver/prior_residuals.hpp"

namespace ccdlane::solver {

bool ReprojectionResidual::evaluate(SolverState& state) {
  const ParameterLayout& layout = *layout_;
  camera_.set_pose(state.pose);
  const int ng = layout.num_global(), nk = layout.num_line_kinds();
  double cost = 0.0;
  PointJacobian d_point;
  PoseJacobian2 d_pose;
  for (std::size_t i = 0; i < picks_.size(); ++i) {
    const Pick& pick = picks_[i];
    const LaneLine& line = state.lines[pick.line];
    const double x = state.x[i];
    const auto pixel = camera_.pixel_from_point(Vec3(x, line_y(line, x), 0.0), &d_point, &d_pose);
    if (!pixel) return false;
    PickBlock& b = state.blocks[i];
    b.r = (*pixel - Vec2(pick.px, pick.py)) * inv_sigma_;
    cost += b.r.squaredNorm();
    for (int k = 0; k < ng; ++k) b.J.col(k) = d_pose.col(layout.global(k)) * inv_sigma_;
    // The road point moves sideways (fixed-frame y) with y0, m and c; along the line with x.
    const Vec2 d_y = d_point.col(1) * inv_sigma_;
    const double basis[kLineParams] = {1.0, x, x * x};
    for (int k = 0; k < nk; ++k) b.J.col(ng + k) = d_y * basis[layout.line_kind(k)];
    b.J.rightCols(kMaxLocalParams - ng - nk).setZero();
    b.Jx = d_point.col(0) * inv_sigma_ + d_y * (line.m + 2.0 * line.c_per_mm * x);
  }
  evaluate_priors(*priors_, layout, state.pose, state.lines.data(), state.priors, cost);
  state.cost = cost;
  return true;
}

}  // namespace ccdlane::solver
