// Paper residuals. With lens L, cell centre P, D = P - L and road point (x, Y, 0):
//   r1 = (x - xL) Dy - (Y - yL) Dx      r2 = (x - xL) Dz + zL Dx
// L and P move with the pose (CameraModel's pose Jacobians), Y with the line.
#include "core/solver/paper_residual.hpp"

#include <cmath>

namespace ccdlane::solver {

double paper_optimal_x(double a1, double b1, double q, double a2, double b2) {
  double x = -(a1 * b1 + a2 * b2) / (a1 * a1 + a2 * a2);
  if (q == 0.0) return x;
  // A curved line makes r1 quadratic in x: minimise by Newton with the exact second
  // derivative where it is positive (Gauss-Newton's otherwise), from the straight-line x.
  for (int it = 0; it < 20; ++it) {
    const double r1 = (a1 - q * x) * x + b1, r2 = a2 * x + b2;
    const double d1 = a1 - 2.0 * q * x;
    const double grad = r1 * d1 + r2 * a2;
    const double gauss_newton = d1 * d1 + a2 * a2;
    const double exact = gauss_newton - 2.0 * q * r1;
    const double step = grad / (exact > 0.0 ? exact : gauss_newton);
    x -= step;
    if (!(std::abs(step) > 1e-15 * std::abs(x))) break;
  }
  return x;
}

bool PaperResidual::evaluate(SolverState& state) {
  const ParameterLayout& layout = *layout_;
  camera_.set_pose(state.pose);
  const int np = layout.num_pose(), ng = layout.num_global(), nk = layout.num_line_kinds();
  const int shared_c = layout.shared_curvature_index();
  PoseJacobian3 dL, dP;
  const Vec3 L = camera_.lens_centre(&dL);
  double cost = 0.0;
  for (std::size_t i = 0; i < picks_.size(); ++i) {
    const RoadLine& line = state.lines[picks_[i].line];
    const Vec3 D = camera_.cell_centre(ideal_px_[i], &dP) - L;
    const PoseJacobian3 dD = dP - dL;
    // r1 = a1 x + b1 - q x^2, r2 = a2 x + b2 (from the definitions above).
    const double q = line.c_per_mm * D.x();
    const double a1 = D.y() - line.m * D.x(), b1 = -L.x() * D.y() - (line.y0_mm - L.y()) * D.x();
    const double a2 = D.z(), b2 = -L.x() * D.z() + L.z() * D.x();
    const double x = paper_optimal_x(a1, b1, q, a2, b2);
    state.x[i] = x;
    const double Y = line_y(line, x), ax = x - L.x(), ay = Y - L.y();

    const Vec2 r(ax * D.y() - ay * D.x(), ax * D.z() + L.z() * D.x());
    cost += r.squaredNorm();
    PickJacobian J;
    for (int k = 0; k < np; ++k) {
      const int p = layout.global(k);
      J(0, k) = -dL(0, p) * D.y() + ax * dD(1, p) + dL(1, p) * D.x() - ay * dD(0, p);
      J(1, k) = -dL(0, p) * D.z() + ax * dD(2, p) + dL(2, p) * D.x() + L.z() * dD(0, p);
    }
    const double basis[kLineParams] = {1.0, x, x * x};
    if (shared_c >= 0) J.col(shared_c) = Vec2(-D.x() * basis[kCurvature], 0.0);
    for (int k = 0; k < nk; ++k) J.col(ng + k) = Vec2(-D.x() * basis[layout.line_kind(k)], 0.0);
    const Vec2 Jx(D.y() - (line.m + 2.0 * line.c_per_mm * x) * D.x(), D.z());
    state.rows->set(static_cast<int>(i), r, J, Jx, ng + nk);
  }
  state.priors.count = 0;  // the paper's index has no priors
  state.cost = cost;
  return state.rows->complete(static_cast<int>(picks_.size()));
}

}  // namespace ccdlane::solver
