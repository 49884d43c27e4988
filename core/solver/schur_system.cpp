// Schur elimination of the per-pick x_i. A pick's rows touch the globals, its own line
// and its x, so its contribution is accumulated in a zero-padded local block per line
// (fixed size, vectorised) and scattered into the reduced matrix once per line.
#include "core/solver/schur_system.hpp"

#include <array>

namespace ccdlane::solver {

void build_reduced_system(const ParameterLayout& layout, std::span<const Pick> picks, const SolverState& state,
                          double lambda, ReducedMatrix& N, ReducedVector& g) {
  const int n = layout.size(), ng = layout.num_global(), nk = layout.num_line_kinds();
  const int num_lines = layout.num_lines();
  std::array<LocalMatrix, kMaxLaneLines> H;
  std::array<LocalVector, kMaxLaneLines> h;
  for (int j = 0; j < num_lines; ++j) {
    H[j].setZero();
    h[j].setZero();
  }
  const double damping = 1.0 + lambda;
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const PickBlock& b = state.blocks[i];
    const int j = picks[i].line;
    // [J Jx]^T [J Jx] = [[A, w], [w^T, c]]; eliminating x leaves A - w w^T / c.
    const LocalVector w = b.J.transpose() * b.Jx;
    const double c = b.Jx.squaredNorm() * damping;
    const double cr = b.Jx.dot(b.r);
    H[j].noalias() += b.J.transpose() * b.J;
    h[j].noalias() += b.J.transpose() * b.r;
    if (c > 0.0) {
      H[j].noalias() -= w * (w.transpose() / c);
      h[j] -= w * (cr / c);
    }
  }

  N.setZero(n, n);
  g.setZero(n);
  for (int j = 0; j < num_lines; ++j) {
    const int o = layout.line_offset(j);
    N.topLeftCorner(ng, ng) += H[j].topLeftCorner(ng, ng);
    N.block(0, o, ng, nk) = H[j].block(0, ng, ng, nk);
    N.block(o, 0, nk, ng) = H[j].block(ng, 0, nk, ng);
    N.block(o, o, nk, nk) = H[j].block(ng, ng, nk, nk);
    g.head(ng) += h[j].head(ng);
    g.segment(o, nk) = h[j].segment(ng, nk);
  }
  for (int k = 0; k < state.priors.count; ++k) {
    const PriorRow& row = state.priors.rows[k];
    N.noalias() += row.a * row.a.transpose();
    g += row.a * row.r;
  }
}

BackSubstitution back_substitute(const ParameterLayout& layout, std::span<const Pick> picks, const SolverState& state,
                                 double lambda, const ReducedVector& step, double* dx) {
  BackSubstitution out;
  const double damping = 1.0 + lambda;
  std::array<LocalVector, kMaxLaneLines> local;
  for (int j = 0; j < layout.num_lines(); ++j) local[j] = layout.gather_local(step, j);
  // Predicted decrease per residual block: |r|^2 - |r + u|^2 = -(2 r.u + u.u), computed
  // from u directly so that it does not vanish in the rounding of two nearly equal costs.
  double decrease = 0.0;
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const PickBlock& b = state.blocks[i];
    const Vec2 Jp = b.J * local[picks[i].line];
    const double c = b.Jx.squaredNorm() * damping;
    dx[i] = c > 0.0 ? -(b.Jx.dot(b.r) + b.Jx.dot(Jp)) / c : 0.0;
    out.x_step_squared_norm += dx[i] * dx[i];
    const Vec2 u = Jp + b.Jx * dx[i];
    decrease -= 2.0 * b.r.dot(u) + u.squaredNorm();
  }
  for (int k = 0; k < state.priors.count; ++k) {
    const PriorRow& row = state.priors.rows[k];
    const double u = row.a.dot(step);
    decrease -= 2.0 * row.r * u + u * u;
  }
  out.predicted_decrease = decrease;
  return out;
}

}  // namespace ccdlane::solver
