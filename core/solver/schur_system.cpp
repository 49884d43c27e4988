// Schur elimination of the per-pick x_i, over the picks' rows (PickRows) line by line.
//
// Eliminating x_i with curvature |Jx|^2 (1 + lambda) leaves J^T P J with
//   P = I - Jx Jx^T / (|Jx|^2 (1 + lambda)) = (b_u b_u^T + lambda / (1 + lambda) b_x b_x^T) / |Jx|^2
// in the pick's directions b_u, b_x: two rank-one rows, one when undamped. Each entry of
// a line's block is then a weighted dot product over the line's picks.
#include "core/solver/schur_system.hpp"

#include <limits>

#include "core/solver/fixed_size.hpp"

namespace ccdlane::solver {

static_assert(kMaxLocalParams <= kMaxFixedSize, "every local size has its fixed-size kernels");

PickRows::PickRows(int max_picks) {
  for (Array* a : {&r0, &r1, &jx0, &jx1, &ru, &rx, &w}) a->setZero(max_picks);
  for (int k = 0; k < kMaxLocalParams; ++k) {
    au[k].setZero(max_picks);
    ax[k].setZero(max_picks);
  }
}

void PickRows::set(int i, const Vec2& r, const PickJacobian& J, const Vec2& Jx, int m) {
  r0[i] = r.x();
  r1[i] = r.y();
  jx0[i] = Jx.x();
  jx1[i] = Jx.y();
  const Vec2 bu(-Jx.y(), Jx.x());
  for (int k = 0; k < m; ++k) {
    au[k][i] = bu.dot(J.col(k));
    ax[k][i] = Jx.dot(J.col(k));
  }
}

bool PickRows::complete(int n) {
  const double *j0 = jx0.data(), *j1 = jx1.data(), *a = r0.data(), *b = r1.data();
  double *out_u = ru.data(), *out_x = rx.data(), *out_w = w.data();
#pragma GCC ivdep
  for (int i = 0; i < n; ++i) {  // one pass, vectorised (the arrays are distinct)
    out_u[i] = -j1[i] * a[i] + j0[i] * b[i];
    out_x[i] = j0[i] * a[i] + j1[i] * b[i];
    out_w[i] = 1.0 / (j0[i] * j0[i] + j1[i] * j1[i]);
  }
  // |Jx|^2 = 0 (or below the reciprocal's range) leaves w infinite, NaN leaves NaN.
  return (w.head(n) < std::numeric_limits<double>::infinity()).all();
}

namespace {

// Each pick's two rows into its line's parts as weighted rank-one updates of fixed size M
// (unrolled and vectorised over the parameters): with a dozen picks per line, one pass
// over the picks beats M (M + 3) short dot products over them. Measured slower too: the
// lower triangles only (scalar code) and the sums vectorised over the picks.
template <int M>
void accumulate_picks(const ParameterLayout& layout, const LineSegments& segments, const PickRows& rows,
                      LineNormals& out) {
  using Row = Eigen::Matrix<double, M, 1>;
  for (int j = 0; j < layout.num_lines(); ++j) {
    Eigen::Matrix<double, M, M> Hf = Eigen::Matrix<double, M, M>::Zero(), Hd = Hf;
    Row hf = Row::Zero(), hd = Row::Zero();
    for (int i = segments.begin[j]; i < segments.begin[j + 1]; ++i) {
      Row a, x;
      for (int k = 0; k < M; ++k) {
        a[k] = rows.au[k][i];
        x[k] = rows.ax[k][i];
      }
      const Row aw = a * rows.w[i], xw = x * rows.w[i];
      Hf.noalias() += aw * a.transpose();
      Hd.noalias() += xw * x.transpose();
      hf += aw * rows.ru[i];
      hd += xw * rows.rx[i];
    }
    out.H_fixed[j].template topLeftCorner<M, M>() = Hf;
    out.H_damped[j].template topLeftCorner<M, M>() = Hd;
    out.h_fixed[j].template head<M>() = hf;
    out.h_damped[j].template head<M>() = hd;
  }
}

// Where line j's local parameters sit in the reduced vector.
template <int M>
std::array<int, M> reduced_indices(const ParameterLayout& layout, int j) {
  std::array<int, M> index{};
  for (int k = 0; k < M; ++k) index[k] = layout.reduced_index(j, k);
  return index;
}

// Each line's block at damping lambda, scattered into the reduced system (plain loops:
// the sizes are tiny, and Eigen's dynamic block expressions cost more than the
// arithmetic here).
template <int M>
void scatter_lines(const ParameterLayout& layout, const LineNormals& parts, double lambda, ReducedMatrix& N,
                   ReducedVector& g) {
  const double damped_share = lambda / (1.0 + lambda);
  for (int j = 0; j < layout.num_lines(); ++j) {
    const std::array<int, M> at = reduced_indices<M>(layout, j);
    const auto H = (parts.H_fixed[j].template topLeftCorner<M, M>() +
                    damped_share * parts.H_damped[j].template topLeftCorner<M, M>())
                       .eval();
    const auto h = (parts.h_fixed[j].template head<M>() + damped_share * parts.h_damped[j].template head<M>()).eval();
    for (int c = 0; c < M; ++c) {
      for (int k = 0; k < M; ++k) N(at[k], at[c]) += H(k, c);
      g[at[c]] += h[c];
    }
  }
}

// x_i steps for a reduced step, and the linearised cost decrease, one pass over the
// picks with M local parameters fixed at compile time (as accumulate_picks).
template <int M>
BackSubstitution back_substitute_picks(const ParameterLayout& layout, const LineSegments& segments,
                                       const PickRows& rows, double lambda, const ReducedVector& step, double* dx) {
  const double inv_damping = 1.0 / (1.0 + lambda);
  std::array<const double*, M> au, ax;
  for (int k = 0; k < M; ++k) {
    au[k] = rows.au[k].data();
    ax[k] = rows.ax[k].data();
  }
  const double *ru = rows.ru.data(), *rx = rows.rx.data(), *w = rows.w.data();
  double decrease = 0.0, dx2 = 0.0;
  for (int j = 0; j < layout.num_lines(); ++j) {
    const std::array<int, M> at = reduced_indices<M>(layout, j);
    std::array<double, M> delta;
    for (int k = 0; k < M; ++k) delta[k] = step[at[k]];
      // Vectorised over the line's picks, the two sums included (their order is the
      // compiler's, which the rounding of a step's norm and its predicted decrease allows).
#pragma omp simd reduction(+ : decrease, dx2)
    for (int i = segments.begin[j]; i < segments.begin[j + 1]; ++i) {
      // The change of the pick's residuals along b_u (p) and b_x (q) from the parameters.
      double p = 0.0, q = 0.0;
      for (int k = 0; k < M; ++k) {
        p += au[k][i] * delta[k];
        q += ax[k][i] * delta[k];
      }
      // x_i's step, and with it q's change Jx.Jx dx_i = -(rx + q) / (1 + lambda).
      const double absorbed = -(rx[i] + q) * inv_damping;
      const double step_x = absorbed * w[i];
      dx[i] = step_x;
      q += absorbed;
      dx2 += step_x * step_x;
      // Predicted decrease: |r|^2 - |r + u|^2 = -(2 r.u + u.u) for the change u of the
      // residuals, from u directly (along b_u and b_x, each of squared length 1 / w) so
      // that it does not vanish in the rounding of two nearly equal costs.
      decrease -= (2.0 * (ru[i] * p + rx[i] * q) + p * p + q * q) * w[i];
    }
  }
  BackSubstitution out;
  out.predicted_decrease = decrease;
  out.x_step_squared_norm = dx2;
  return out;
}

// f<M>() with M = the layout's local size. A layout with nothing free (local size 0) has
// no reduced system to build: LaneSolver refuses such a request (invalid_input) before it
// gets here, so meeting one is a caller's bug, which the dispatch stops on. Every other
// layout has 1..kMaxLocalParams local parameters (the globals and one line's kinds), all
// with their fixed-size kernels (the static_assert above).
template <class F>
decltype(auto) with_local_size(const ParameterLayout& layout, F&& f) {
  return with_fixed_size(layout.local_size(), f);
}

}  // namespace

void accumulate_normals(const ParameterLayout& layout, const LineSegments& segments, SolverState& state) {
  with_local_size(layout, [&]<int M>() { accumulate_picks<M>(layout, segments, *state.rows, state.normals); });
}

void build_reduced_system(const ParameterLayout& layout, const SolverState& state, double lambda, ReducedMatrix& N,
                          ReducedVector& g) {
  const int n = layout.size();
  N.setZero(n, n);
  g.setZero(n);
  with_local_size(layout, [&]<int M>() { scatter_lines<M>(layout, state.normals, lambda, N, g); });
  for (int p = 0; p < state.priors.count; ++p) {
    const PriorRow& row = state.priors.rows[p];
    for (int c = 0; c < row.size; ++c) {
      for (int k = 0; k < row.size; ++k) N(row.index[k], row.index[c]) += row.value[k] * row.value[c];
      g[row.index[c]] += row.value[c] * row.r;
    }
  }
}

BackSubstitution back_substitute(const ParameterLayout& layout, const LineSegments& segments, const SolverState& state,
                                 double lambda, const ReducedVector& step, double* dx) {
  BackSubstitution out;
  with_local_size(layout,
                  [&]<int M>() { out = back_substitute_picks<M>(layout, segments, *state.rows, lambda, step, dx); });
  for (int k = 0; k < state.priors.count; ++k) {
    const PriorRow& row = state.priors.rows[k];
    double u = 0.0;
    for (int e = 0; e < row.size; ++e) u += row.value[e] * step[row.index[e]];
    out.predicted_decrease -= 2.0 * row.r * u + u * u;
  }
  return out;
}

}  // namespace ccdlane::solver
