// Schur elimination of the per-pick x_i. A pick's rows touch the globals, its own line
// and its x, so its contribution is accumulated in a zero-padded local block per line
// (fixed size, vectorised) and scattered into the reduced matrix once per line.
#include "core/solver/schur_system.hpp"

#include <array>

namespace ccdlane::solver {

namespace {

// Calls f.template operator()<M>() with M = the layout's local size, a compile-time
// constant in each branch (1 .. kMaxLocalParams).
template <class F>
decltype(auto) with_local_size(int m, F&& f) {
  switch (m) {
    case 1: return f.template operator()<1>();
    case 2: return f.template operator()<2>();
    case 3: return f.template operator()<3>();
    case 4: return f.template operator()<4>();
    case 5: return f.template operator()<5>();
    case 6: return f.template operator()<6>();
    case 7: return f.template operator()<7>();
    default: return f.template operator()<kMaxLocalParams>();
  }
}

// Adds each pick's Schur-reduced contribution to its line's local block, for M local
// columns (fixed at compile time so the small products unroll and vectorise).
//
// Eliminating x_i with curvature |Jx|^2 (1 + lambda) leaves J^T P J with
//   P = I - Jx Jx^T / (|Jx|^2 (1 + lambda)) = (u u^T + lambda / (1 + lambda) Jx Jx^T) / |Jx|^2,
// u = Jx turned by 90 degrees (in 2-D, I - Jx Jx^T / |Jx|^2 = u u^T / |Jx|^2): two rank-one
// updates, one when undamped, instead of J^T J minus an outer product.
template <int M>
void accumulate_picks(std::span<const Pick> picks, const SolverState& state, double lambda,
                      std::array<LocalMatrix, kMaxLaneLines>& H, std::array<LocalVector, kMaxLaneLines>& h) {
  const double damped_share = lambda / (1.0 + lambda);
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const PickBlock& b = state.blocks[i];
    const int j = picks[i].line;
    const auto J = b.J.template leftCols<M>();
    auto Hj = H[j].template topLeftCorner<M, M>();
    auto hj = h[j].template head<M>();
    const double jj = b.Jx.squaredNorm();
    if (!(jj > 0.0)) {  // x_i does not move this pick: nothing to eliminate
      Hj.noalias() += J.transpose() * J;
      hj.noalias() += J.transpose() * b.r;
      continue;
    }
    const double inv_jj = 1.0 / jj;
    const Vec2 u(-b.Jx.y(), b.Jx.x());
    const Eigen::Matrix<double, 1, M> a = u.transpose() * J;
    const Eigen::Matrix<double, 1, M> a_scaled = a * inv_jj;
    Hj.noalias() += a.transpose() * a_scaled;
    hj.noalias() += a_scaled.transpose() * u.dot(b.r);
    if (damped_share > 0.0) {
      const Eigen::Matrix<double, 1, M> c = b.Jx.transpose() * J;
      const Eigen::Matrix<double, 1, M> c_scaled = c * (damped_share * inv_jj);
      Hj.noalias() += c.transpose() * c_scaled;
      hj.noalias() += c_scaled.transpose() * b.Jx.dot(b.r);
    }
  }
}

// x_i steps for a reduced step, and the linearised cost decrease, for M local columns.
template <int M>
BackSubstitution back_substitute_picks(const ParameterLayout& layout, std::span<const Pick> picks,
                                       const SolverState& state, double lambda, const ReducedVector& step, double* dx) {
  BackSubstitution out;
  const double damping = 1.0 + lambda;
  std::array<Eigen::Matrix<double, M, 1>, kMaxLaneLines> local;
  for (int j = 0; j < layout.num_lines(); ++j) local[j] = layout.gather_local(step, j).template head<M>();
  // Predicted decrease per residual block: |r|^2 - |r + u|^2 = -(2 r.u + u.u), computed
  // from u directly so that it does not vanish in the rounding of two nearly equal costs.
  double decrease = 0.0;
  for (std::size_t i = 0; i < picks.size(); ++i) {
    const PickBlock& b = state.blocks[i];
    const Vec2 Jp = b.J.template leftCols<M>() * local[picks[i].line];
    const double c = b.Jx.squaredNorm() * damping;
    dx[i] = c > 0.0 ? -b.Jx.dot(b.r + Jp) / c : 0.0;
    out.x_step_squared_norm += dx[i] * dx[i];
    const Vec2 u = Jp + b.Jx * dx[i];
    decrease -= 2.0 * b.r.dot(u) + u.squaredNorm();
  }
  out.predicted_decrease = decrease;
  return out;
}

}  // namespace

void build_reduced_system(const ParameterLayout& layout, std::span<const Pick> picks, const SolverState& state,
                          double lambda, ReducedMatrix& N, ReducedVector& g) {
  const int n = layout.size(), ng = layout.num_global();
  const int num_lines = layout.num_lines();
  std::array<LocalMatrix, kMaxLaneLines> H;
  std::array<LocalVector, kMaxLaneLines> h;
  for (int j = 0; j < num_lines; ++j) {
    H[j].setZero();
    h[j].setZero();
  }
  with_local_size(layout.local_size(), [&]<int M>() { accumulate_picks<M>(picks, state, lambda, H, h); });

  // Scatter each line's local block: its globals overlap every other line's, its own
  // kinds sit at the line's offset. Plain loops: the sizes are tiny, and Eigen's dynamic
  // block expressions cost more than the arithmetic here.
  const int m = layout.local_size();
  N.setZero(n, n);
  g.setZero(n);
  for (int j = 0; j < num_lines; ++j) {
    const int shift = layout.line_offset(j) - ng;
    const auto reduced = [&](int local) { return local < ng ? local : local + shift; };
    for (int c = 0; c < m; ++c) {
      const int rc = reduced(c);
      for (int k = 0; k < m; ++k) N(reduced(k), rc) += H[j](k, c);
      g[rc] += h[j][c];
    }
  }
  for (int p = 0; p < state.priors.count; ++p) {
    const PriorRow& row = state.priors.rows[p];
    for (int c = 0; c < n; ++c) {
      if (row.a[c] == 0.0) continue;  // a prior touches one or two parameters
      for (int k = 0; k < n; ++k) N(k, c) += row.a[k] * row.a[c];
      g[c] += row.a[c] * row.r;
    }
  }
}

BackSubstitution back_substitute(const ParameterLayout& layout, std::span<const Pick> picks, const SolverState& state,
                                 double lambda, const ReducedVector& step, double* dx) {
  BackSubstitution out = with_local_size(layout.local_size(), [&]<int M>() {
    return back_substitute_picks<M>(layout, picks, state, lambda, step, dx);
  });
  for (int k = 0; k < state.priors.count; ++k) {
    const PriorRow& row = state.priors.rows[k];
    const double u = row.a.dot(step);
    out.predicted_decrease -= 2.0 * row.r * u + u * u;
  }
  return out;
}

}  // namespace ccdlane::solver
